#pragma once
// A person's landmarks in 3-D from several views of their turning head. One frontal picture fixes the
// CANDIDE-3 shape in the image plane but not in depth (../shared/notes/face.md §4): where on the
// person's face the detector puts a brow end or the nose's base, front to back, is not seen, and that
// depth error shows as a pitch and distance bias of every later pose (docs/face.md). Views with the
// head turned left, right, up and down see those depths. This is a small bundle adjustment with the
// camera known (Ceres): the view poses and the landmarks' 3-D points are refined together, each point pulled
// towards its model position by a prior (the model is right to a few millimetres; a point seen in
// few views must not wander), and the result is put back to the person's interpupillary distance,
// which is the only metric information (a monocular sequence has no scale of its own).
#include <Eigen/Geometry>
#include <vector>

#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

struct LandmarkView {
  Eigen::Matrix2Xd pixels;               // 2 x n, undistorted, the model's landmarks in this view
  Eigen::Isometry3d T_cam_face_initial;  // e.g. the tracker's pose of that frame
};

struct MultiViewOptions {
  double pixel_sigma_px = 1.5;  // landmark detection noise
  // How far a landmark may sit from its model point, a priori: in the face's plane (x, y), which the
  // frontal registration saw, and in depth (z), which it did not. The tight in-plane prior also
  // fixes the face frame's orientation: it is the one in which the refined points, seen from the
  // front, fall on the registered ones.
  double prior_sigma_m = 0.002;
  double prior_depth_sigma_m = 0.030;
  double huber_px = 3.0;         // larger residuals (a slipped landmark in one view) weigh less
  int max_iterations = 50;       // of the joint Levenberg-Marquardt
};

struct MultiViewFit {
  Eigen::Matrix3Xd points_m;               // refined landmarks, face frame, at the person's IPD
  std::vector<Eigen::Isometry3d> poses;    // per view, for the refined points
  double rms_before_px = 0, rms_after_px = 0;  // over all views
};

// Refines `model_points_m` (3 x n, metres, face frame; the registered shape's landmarks) from `views`
// (at least 3, each with n pixels). `model` names the eye landmarks that define the IPD. Throws
// std::invalid_argument on size mismatches or too few views.
MultiViewFit refine_landmarks_from_views(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& model_points_m,
                                         const std::vector<LandmarkView>& views, const IdealPinhole& camera,
                                         double interpupillary_distance_m, const MultiViewOptions& options = {});

}  // namespace labo::face
