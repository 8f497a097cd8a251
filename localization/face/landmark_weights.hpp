#pragma once
// How much each rigid landmark is trusted by the pose refinement (the LM's per-point weights).
//
// Two independent factors, multiplied:
//  - a per-landmark noise model: dlib's ERT places some landmarks far less reliably than others (the
//    outer ends of the brows, at the face's contour, and the mouth corners worst; the nose ridge and
//    the eyes best), and in a real face the brows and lips also move with expression. The weight is
//    (σ_ref / σ_i)², σ_i the landmark group's typical error in interocular distances.
//  - a turn-dependent factor for the side of the face turned away from the camera (optional).
#include <Eigen/Core>
#include <vector>

namespace labo::face {

// Typical error of iBUG-68 landmark `id` (17-59) as a fraction of the interocular distance, by group;
// measured on `labodrone-bench bench face` (seed 1, frames within 15° of frontal, RMS of each landmark's
// error against the rendered head's true landmarks), rounded per semantic group. Throws
// std::invalid_argument for ids outside 17-59.
double landmark_noise_iod(int ibug_id);

// (σ_ref / σ_i)² for each id (σ_ref: the most reliable group), in the ids' order.
Eigen::VectorXd landmark_noise_weights(const std::vector<int>& ibug_ids);

// Multiplies weights(i) by 1 / (1 + a_i (yaw / far_side_yaw)²), a_i in [0, 1] how far point i lies
// on the side turned away (face-frame x beyond 5 cm from the middle: 1). Positive yaw turns the
// subject's right (face -x) away from the camera. No effect when far_side_yaw_rad <= 0.
void apply_far_side_weights(const Eigen::Matrix3Xd& points_face, double yaw_rad, double far_side_yaw_rad,
                            Eigen::VectorXd& weights);

}  // namespace labo::face
