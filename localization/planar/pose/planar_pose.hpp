#pragma once
// Camera-from-object pose of a planar object from its four corners: IPPE (ippe.hpp, LaboDrone's own,
// equal to OpenCV's SOLVEPNP_IPPE to 1e-9 and allocation-free) on the corners at physical size,
// which returns the two poses a plane seen from afar cannot tell apart. The ambiguity is resolved before anything else uses the pose, so that the
// pose-jump loss test does not fire on a flip:
//  1. a candidate must put the panel in front of the camera with its front towards it, and
//     reproject within `max_reprojection_px`;
//  2. when one candidate reprojects clearly worse (by more than 2x and 1 px), the other wins;
//  3. otherwise the candidate closer in rotation to the previous pose wins (continuity), and with
//     no previous pose the lower reprojection error wins but the result is flagged ambiguous.
// Image points are in the undistorted image (pinhole K without distortion).
#include <array>
#include <optional>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "localization/planar/pose/ippe.hpp"

namespace labo::planar {

struct PlanarPose {
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();
  double reprojection_error_px = 0;  // RMS over the 4 corners
  bool ambiguous = false;            // the two IPPE solutions could not be separated by the data
  double alternative_error_px = 0;   // the rejected solution's reprojection error
  double alternative_angle_rad = 0;  // rotation between the two solutions
  // The rejected solution fits the corners about as well and is a distinct pose (rule 3 decided).
  bool alternative_plausible = false;
  Eigen::Isometry3d T_alternative = Eigen::Isometry3d::Identity();  // the rejected solution (if any)
};

class PlanarPoseSolver {
 public:
  // `K` without skew, `object_corners` in the object's z = 0 plane (std::invalid_argument otherwise).
  // Candidates reprojecting worse than `max_reprojection_px` (RMS) are refused: the corners then do
  // not come from a rigid panel of this size seen through this camera (a mirror image, a wrong H).
  PlanarPoseSolver(const cv::Matx33d& K, const std::array<cv::Point3d, 4>& object_corners,
                   double max_reprojection_px = 4.0);
  // Empty when no candidate is physically possible. `previous` is the last accepted pose. Allocates nothing.
  std::optional<PlanarPose> solve(const std::array<cv::Point2d, 4>& image_corners,
                                  const std::optional<Eigen::Isometry3d>& previous) const;
  // The same from four other points of the object's plane (object x, y in metres) and their images:
  // a panel larger than the view, whose corners lie far outside the image, is solved from points in
  // view (the corners extrapolated by the homography carry its errors magnified).
  std::optional<PlanarPose> solve(const std::array<Eigen::Vector2d, 4>& object_xy, const std::array<cv::Point2d, 4>& image_points,
                                  const std::optional<Eigen::Isometry3d>& previous) const;

 private:
  IppeIntrinsics intrinsics_;
  std::array<Eigen::Vector2d, 4> object_xy_;
  double max_reprojection_px_;
};

// Rotation angle between two orientations, radians.
double rotation_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace labo::planar
