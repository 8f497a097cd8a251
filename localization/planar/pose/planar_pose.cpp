#include "localization/planar/pose/planar_pose.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace labo::planar {

double rotation_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

PlanarPoseSolver::PlanarPoseSolver(const cv::Matx33d& K, const std::array<cv::Point3d, 4>& object_corners,
                                   double max_reprojection_px)
    : intrinsics_{K(0, 0), K(1, 1), K(0, 2), K(1, 2)}, max_reprojection_px_(max_reprojection_px) {
  if (K(0, 1) != 0.0) throw std::invalid_argument("PlanarPoseSolver: the camera matrix has a skew");
  for (std::size_t i = 0; i < 4; ++i) {
    if (object_corners[i].z != 0.0) throw std::invalid_argument("PlanarPoseSolver: the object corners are not in z = 0");
    object_xy_[i] = Eigen::Vector2d(object_corners[i].x, object_corners[i].y);
  }
}

std::optional<PlanarPose> PlanarPoseSolver::solve(const std::array<cv::Point2d, 4>& image_corners,
                                                  const std::optional<Eigen::Isometry3d>& previous) const {
  return solve(object_xy_, image_corners, previous);
}

std::optional<PlanarPose> PlanarPoseSolver::solve(const std::array<Eigen::Vector2d, 4>& object_xy,
                                                  const std::array<cv::Point2d, 4>& image_corners,
                                                  const std::optional<Eigen::Isometry3d>& previous) const {
  struct Candidate {
    Eigen::Isometry3d T;
    double error;
  };
  std::array<Eigen::Vector2d, 4> image;
  for (std::size_t i = 0; i < 4; ++i) image[i] = Eigen::Vector2d(image_corners[i].x, image_corners[i].y);
  const auto solutions = ippe_four_points(object_xy, image, intrinsics_);
  if (!solutions) return std::nullopt;  // degenerate corners (collinear, ...)
  // The solutions come lower reprojection error first.
  std::array<Candidate, 2> candidates;
  std::size_t count = 0;
  for (const IppeSolution& s : *solutions) {
    // In front of the camera, and facing it: the panel's z axis (into the panel) points away.
    if (s.t.z() <= 0 || s.R.col(2).dot(s.t) <= 0 || !(s.rms_px <= max_reprojection_px_)) continue;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = s.R;
    T.translation() = s.t;
    candidates[count++] = {T, s.rms_px};
  }
  if (count == 0) return std::nullopt;
  PlanarPose pose;
  pose.T_cam_object = candidates[0].T;
  pose.reprojection_error_px = candidates[0].error;
  if (count == 1) return pose;
  const Candidate& second = candidates[1];
  pose.alternative_error_px = second.error;
  pose.T_alternative = second.T;
  pose.alternative_angle_rad = rotation_angle(candidates[0].T.linear(), second.T.linear());
  const bool clearly_worse = second.error > std::max(2.0 * candidates[0].error, candidates[0].error + 1.0);
  const bool same_pose = pose.alternative_angle_rad < 2.0 * 3.14159265358979 / 180.0;
  if (clearly_worse || same_pose) return pose;
  pose.alternative_plausible = true;
  if (previous) {
    const double a0 = rotation_angle(previous->linear(), candidates[0].T.linear());
    const double a1 = rotation_angle(previous->linear(), second.T.linear());
    if (a1 < a0) {
      pose.T_cam_object = second.T;
      pose.reprojection_error_px = second.error;
      pose.alternative_error_px = candidates[0].error;
      pose.T_alternative = candidates[0].T;
    }
    return pose;
  }
  pose.ambiguous = true;
  return pose;
}

}  // namespace labo::planar
