#pragma once
// The depth of a person's landmarks from several views of their turning head: a small bundle
// adjustment over the face's rigid shape (structure from motion of the face, camera known).
//
// One frontal picture fixes the registered shape in the image plane but not in depth
// (../shared/notes/face.md §4), and a depth error of the model shows as a pitch (and distance) bias of
// every later pose (docs/face.md). Views with the head turned see those depths. What is refined is
// deliberately small: the poses of the views and a few *depth components* of the landmarks (the
// in-plane positions the frontal picture saw stay as they are):
//   z_i += Σ_k c_k · b_k(i)
// with the components b_k built from the registered points themselves: the depth profile (a gain:
// the whole face deeper or shallower, the main error a wrong shape makes) and one offset per facial
// region (brows, nose bridge, nose base, eyes, mouth). Every component is made orthogonal to
// {1, x_i, y_i} over the landmarks: a depth change linear in x or y is, to first order, a small yaw or
// pitch of the whole face, i.e. of the face frame itself, which a sequence cannot tell from the
// poses (a gauge freedom: left free it would tilt the frame and bias every later angle), and a
// constant is a move of the face's origin. Each coefficient is pulled towards 0 by a prior.
//
// Few parameters, because the depth against the rotation angle is weakly observable from small turns
// (the bas-relief ambiguity: for small angles a deeper face turned less looks the same; only the
// foreshortening, second order in the angle, and the perspective tell them apart), and the
// landmark detector's systematic errors on turned heads would otherwise be fitted as shape.
//
// Bad input is refused with a reason and changes nothing: too few views, too little yaw or pitch
// spread among them, a fit that diverges (non-finite, worse than the start, too large a residual)
// or a result beyond what a face plausibly differs from its model.
#include <Eigen/Geometry>
#include <numbers>
#include <string>
#include <vector>

#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

struct DepthRefinementOptions {
  // Which views may refine a shape.
  int min_views = 10;
  double min_yaw_span_rad = 20 * std::numbers::pi / 180;    // e.g. the head turned 10° left and 10° right
  double min_pitch_span_rad = 12 * std::numbers::pi / 180;  // and nodded 6° up and 6° down
  // The fit.
  double pixel_sigma_px = 1.5;       // landmark detection noise
  double huber_px = 3.0;             // larger residuals (a slipped landmark in one view) weigh less
  double prior_sigma_m = 0.004;      // of each component's coefficient (the component's RMS depth change)
  // Each landmark's own depth (beyond the components, the tilts and the origin still excluded), with
  // this prior; 0: the components only. A detected landmark is not exactly at the model point the
  // mapping names (e.g. a brow's outer end lies on the temple, well behind the model's brow).
  double landmark_prior_sigma_m = 0.0;
  int max_iterations = 30;
  // Divergence and plausibility: refused beyond these.
  double max_rms_px = 3.0;           // landmark fit over the views after the refinement
  double max_depth_change_m = 0.015; // of any landmark
};

// One view: the model's landmarks in it (undistorted pixels, model column order) and a first pose,
// e.g. the tracker's.
struct DepthView {
  Eigen::Matrix2Xd pixels;
  Eigen::Isometry3d T_cam_face_initial = Eigen::Isometry3d::Identity();
};

struct DepthRefinement {
  bool accepted = false;
  std::string reason;                 // why refused ("" when accepted)
  Eigen::VectorXd depth_change_m;     // per landmark (model column order); zero when refused
  Eigen::VectorXd coefficients_m;     // per component
  std::vector<Eigen::Isometry3d> poses;  // per view, for the refined points
  int views = 0;
  double yaw_span_rad = 0, pitch_span_rad = 0;  // of the views' first poses, max - min
  double rms_before_px = 0, rms_after_px = 0;   // over all views, the registered and the refined points
  int iterations = 0;
};

// The depth components for `points_m` (3 x n, face frame, the registered landmarks of `model`):
// columns of an n x k matrix, orthogonal to {1, x, y} and to each other, each of RMS 1 (so that a
// coefficient is the RMS depth change it makes, in metres).
Eigen::MatrixXd depth_components(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points_m);

// Refines the depth of `points_m` from `views`, in the components (and, with a landmark prior, each
// landmark's own depth). Throws std::invalid_argument on size mismatches
// (a programming error); bad views are a refusal (accepted = false, reason set), not an exception.
DepthRefinement refine_depth_from_views(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points_m,
                                        const std::vector<DepthView>& views, const IdealPinhole& camera,
                                        const DepthRefinementOptions& options = {});

}  // namespace labo::face
