#include "localization/face/face_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace labo::face {

namespace {
const Eigen::Matrix3d& facing_camera() {
  static const Eigen::Matrix3d F = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return F;
}
}  // namespace

Eigen::Matrix3d head_rotation(const HeadAngles& a) {
  const Eigen::Matrix3d Q = (Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(a.roll, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  return Q * facing_camera();
}

HeadAngles head_angles(const Eigen::Matrix3d& R_cam_face) {
  const Eigen::Matrix3d Q = R_cam_face * facing_camera();
  HeadAngles a;
  a.pitch = std::asin(std::clamp(-Q(1, 2), -1.0, 1.0));
  a.yaw = std::atan2(Q(0, 2), Q(2, 2));
  a.roll = std::atan2(Q(1, 0), Q(1, 1));
  return a;
}

}  // namespace labo::face
