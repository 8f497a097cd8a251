#include "control/mission.hpp"

#include <cmath>
#include <cstdio>

#include "core/frames.hpp"

namespace labo::control {

PoseTarget standoff_target(const Eigen::Isometry3d& T_world_target, double distance_m, const Eigen::Vector3d& centre_ray) {
  const Eigen::Vector3d centre = T_world_target.translation();
  Eigen::Vector3d into = T_world_target.linear().col(2);
  into.z() = 0;
  if (into.norm() < 1e-6) into = Eigen::Vector3d::UnitX();  // a horizontal target: look along x
  into.normalize();
  // Camera axes when level and facing the target: z = into, y = down, x = y cross z (right).
  const Eigen::Vector3d down(0, 0, -1);
  const Eigen::Vector3d right = down.cross(into);
  const Eigen::Vector3d camera = centre - distance_m * (centre_ray.x() * right + centre_ray.y() * down + into);
  const double camera_forward = T_body_cam_front().translation().x();
  PoseTarget target;
  target.position = camera - camera_forward * into;
  target.yaw = std::atan2(into.y(), into.x());
  return target;
}

Eigen::Vector3d image_centre_ray(double fx, double fy, double cx, double cy, int width, int height) {
  return {(0.5 * width - cx) / fx, (0.5 * height - cy) / fy, 1.0};
}

Eigen::Isometry3d place_in_world(const fusion::PoseEstimate& pose, CameraId camera, const Eigen::Isometry3d& T_cam_target) {
  const Eigen::Isometry3d T_body_cam = camera == CameraId::Front ? T_body_cam_front() : T_body_cam_bottom();
  return pose.T_world_body * T_body_cam * T_cam_target;
}

Eigen::Isometry3d world_pose_of(const fusion::TargetObservation& obs, const fusion::PoseEstimate& pose, CameraId camera) {
  return obs.placed_in_world ? obs.T_world_target : place_in_world(pose, camera, obs.T_cam_target);
}

double camera_distance(const fusion::TargetObservation& obs) { return obs.T_cam_target.translation().norm(); }

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", s);
  return buf;
}

}  // namespace labo::control
