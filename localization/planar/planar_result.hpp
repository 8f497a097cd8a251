#pragma once
// What PlanarObjectLocalizer reports for each frame.
#include <array>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/time.hpp"

namespace labo::planar {

enum class PlanarState { Searching, Detected, Tracking, Lost };
// How the pose was found: detection far (template matching) or near (features: PlanarConfig::near_detector,
// the paper's SIFT or a binary detector), or tracking (ECC or LaboDrone's IC).
enum class PlanarMethod { None, TemplateMatching, Features, Ecc, InverseCompositional };
// Why there is no pose in this frame (None when there is one).
enum class PlanarLoss {
  None,
  NotFound,        // detection ran and did not find the object
  NoConvergence,   // the tracker did not converge (OpenCV's ECC threw, or diverged)
  LowCorrelation,  // aligned, but the correlation with the template is below alpha
  OutOfView,       // too little of the panel inside the image
  PoseJump,        // the camera moved more than D since the previous frame
  TurnJump,        // the camera turned more than beta since the previous frame
  NoPose,          // no physically possible pose (behind the camera, seen from the back)
  BadFrame,        // empty, not 8-bit grey, or not the camera's size: refused, state unchanged
};

const char* to_string(PlanarState s);
const char* to_string(PlanarMethod m);
const char* to_string(PlanarLoss l);

struct PlanarResult {
  Seconds t = 0;
  PlanarState state = PlanarState::Searching;
  PlanarLoss reason = PlanarLoss::None;
  const char* detail = "";  // the tracker's or the check's own words (static text)
  PlanarMethod method = PlanarMethod::None;

  bool has_pose = false;  // true exactly when state is Detected or Tracking
  // Original template pixels -> pixels of the undistorted image (the camera's K, no distortion).
  cv::Matx33d H = cv::Matx33d::eye();
  // The panel's corners in the raw (distorted) frame, clockwise from the template's top-left.
  std::array<cv::Point2d, 4> image_corners{};
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();
  double distance_m = 0;
  double quality = 0;                // [0, 1]: correlation margin x the larger in-view fraction x ambiguity
  // 1-sigma uncertainties of T_cam_object along its worst-determined direction: from the SE(3)
  // refinement's covariance when it ran (pose_refined), else from the corners' noise (approximate).
  // Both grow with the distance; the rotation's mostly as the tilt of the panel seen face-on.
  double position_sigma_m = 0;
  double rotation_sigma_rad = 0;
  bool pose_refined = false;         // the photometric SE(3) refinement gave the pose (se3_pose_refiner.hpp)
  bool footprint_model = false;      // it fitted the raw frame's pixels as footprints (area_pose_refiner.hpp)
  double reprojection_error_px = 0;  // IPPE, RMS over the corners
  double correlation = 0;            // after alignment
  double visible_fraction = 0;       // of the panel's area inside the image
  double image_fraction = 0;         // of the image the panel covers
  bool pose_ambiguous = false;       // the two IPPE poses could not be told apart
  int inliers = 0;                   // near detections (features): RANSAC inliers
  // Gauss-Newton iterations of this frame's SE(3) refinements (every blur hypothesis and IPPE branch
  // tried): the refinement's cost, independent of the machine's load.
  int refinement_iterations = 0;
};

}  // namespace labo::planar
