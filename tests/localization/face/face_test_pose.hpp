#pragma once
// A face pose from head angles in degrees and a translation (metres), for the face tests.
#include <Eigen/Geometry>
#include <numbers>

#include "localization/face/face_geometry.hpp"

namespace labo::face::testing {

inline Eigen::Isometry3d pose(double yaw_deg, double pitch_deg, double roll_deg, const Eigen::Vector3d& t) {
  constexpr double kRad = std::numbers::pi / 180.0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = head_rotation({yaw_deg * kRad, pitch_deg * kRad, roll_deg * kRad});
  T.translation() = t;
  return T;
}

}  // namespace labo::face::testing
