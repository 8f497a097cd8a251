#include "core/frames.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace labo {

std::string to_string(FrameId frame) {
  switch (frame.kind) {
    case FrameKind::World: return "world";
    case FrameKind::Body: return "body";
    case FrameKind::CamFront: return "cam_front";
    case FrameKind::CamBottom: return "cam_bottom";
    case FrameKind::Map: return "map";
    case FrameKind::Object: return "object:" + std::to_string(frame.index);
    case FrameKind::Face: return "face";
  }
  return "?";
}

FramedTransform FramedTransform::operator*(const FramedTransform& rhs) const {
  if (!(from_ == rhs.to_)) {
    throw std::logic_error("cannot compose T_" + to_string(to_) + "_" + to_string(from_) + " with T_" +
                           to_string(rhs.to_) + "_" + to_string(rhs.from_) + ": frames " +
                           to_string(from_) + " and " + to_string(rhs.to_) + " differ");
  }
  return {to_, rhs.from_, T_ * rhs.T_};
}

Eigen::Matrix3d rotation_from_ypr(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d ypr_from_rotation(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double yaw = 0.0;
  double roll = 0.0;
  if (std::abs(R(2, 0)) < 1.0 - 1e-9) {
    yaw = std::atan2(R(1, 0), R(0, 0));
    roll = std::atan2(R(2, 1), R(2, 2));
  } else {
    // Gimbal lock: roll is folded into yaw.
    yaw = std::atan2(-R(0, 1), R(1, 1));
  }
  return {yaw, pitch, roll};
}

double wrap_angle(double rad) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  double r = std::fmod(rad + std::numbers::pi, two_pi);
  if (r < 0) r += two_pi;
  return r - std::numbers::pi;
}

Eigen::Isometry3d make_pose(const Eigen::Vector3d& t, double yaw, double pitch, double roll) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_from_ypr(yaw, pitch, roll);
  T.translation() = t;
  return T;
}

Eigen::Isometry3d T_body_cam_front(const Eigen::Vector3d& offset_body) {
  Eigen::Matrix3d R;  // columns: camera x, y, z axes in body coordinates
  R.col(0) = -Eigen::Vector3d::UnitY();
  R.col(1) = -Eigen::Vector3d::UnitZ();
  R.col(2) = Eigen::Vector3d::UnitX();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = offset_body;
  return T;
}

Eigen::Isometry3d T_body_cam_bottom(const Eigen::Vector3d& offset_body) {
  Eigen::Matrix3d R;
  R.col(0) = -Eigen::Vector3d::UnitY();
  R.col(1) = -Eigen::Vector3d::UnitX();
  R.col(2) = -Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = offset_body;
  return T;
}

}  // namespace labo
