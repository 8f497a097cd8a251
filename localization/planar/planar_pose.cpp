#include "localization/planar/planar_pose.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace labo {

double rotation_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

PlanarPoseSolver::PlanarPoseSolver(const cv::Matx33d& K, const std::array<cv::Point3d, 4>& object_corners,
                                   double max_reprojection_px)
    : K_(K), object_(object_corners), max_reprojection_px_(max_reprojection_px) {}

std::optional<PlanarPose> PlanarPoseSolver::solve(const std::array<cv::Point2d, 4>& image_corners,
                                                  const std::optional<Eigen::Isometry3d>& previous) const {
  struct Candidate {
    Eigen::Isometry3d T;
    double error;
  };
  std::vector<cv::Point3d> object(object_.begin(), object_.end());
  std::vector<cv::Point2d> image(image_corners.begin(), image_corners.end());
  std::vector<cv::Mat> rvecs, tvecs;
  std::vector<double> errors;
  try {
    cv::solvePnPGeneric(object, image, K_, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE, cv::noArray(),
                        cv::noArray(), errors);
  } catch (const cv::Exception&) {
    return std::nullopt;  // degenerate corners (collinear, ...)
  }
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < rvecs.size(); ++i) {
    cv::Matx33d R;
    cv::Rodrigues(rvecs[i], R);
    Eigen::Matrix3d Re;
    cv::cv2eigen(cv::Mat(R), Re);
    const Eigen::Vector3d t(tvecs[i].at<double>(0), tvecs[i].at<double>(1), tvecs[i].at<double>(2));
    // In front of the camera, and facing it: the panel's z axis (into the panel) points away.
    const double error = i < errors.size() ? errors[i] : 0.0;
    if (t.z() <= 0 || Re.col(2).dot(t) <= 0 || !t.allFinite() || !(error <= max_reprojection_px_)) continue;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Re;
    T.translation() = t;
    candidates.push_back({T, error});
  }
  if (candidates.empty()) return std::nullopt;
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.error < b.error; });
  PlanarPose pose;
  pose.T_cam_object = candidates[0].T;
  pose.reprojection_error_px = candidates[0].error;
  if (candidates.size() == 1) return pose;
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

}  // namespace labo
