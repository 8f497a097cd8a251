#include "localization/estimation/landmark.hpp"

#include <algorithm>

namespace labo::estimation {

namespace {
// Kalman weight of a measurement of variance `measured` against a state of variance `self`.
double kalman_weight(double self, double measured) {
  const double sum = self + measured;
  return sum > 0 ? self / sum : 0.5;
}

Eigen::Quaterniond slerp_towards(const Eigen::Matrix3d& from, const Eigen::Matrix3d& to, double k) {
  return Eigen::Quaterniond(from).slerp(std::clamp(k, 0.0, 1.0), Eigen::Quaterniond(to)).normalized();
}
}  // namespace

void Landmark::blend(const Eigen::Isometry3d& T_measured, double k) {
  k = std::clamp(k, 0.0, 1.0);
  const Eigen::Vector3d t = (1.0 - k) * T_world_landmark.translation() + k * T_measured.translation();
  T_world_landmark.linear() = slerp_towards(T_world_landmark.linear(), T_measured.linear(), k).toRotationMatrix();
  T_world_landmark.translation() = t;
}

void Landmark::fuse(const PoseWithVariance& measured) {
  const double kp = kalman_weight(position_var, measured.position_var);
  const double kr = kalman_weight(rotation_var, measured.rotation_var);
  T_world_landmark.translation() += kp * (measured.T.translation() - T_world_landmark.translation());
  T_world_landmark.linear() = slerp_towards(T_world_landmark.linear(), measured.T.linear(), kr).toRotationMatrix();
  position_var = (1.0 - kp) * position_var;
  rotation_var = (1.0 - kr) * rotation_var;
  ++refinements;
}

Landmark place_landmark(const PoseWithVariance& cascade, const PoseWithVariance* surveyed, Seconds t) {
  Landmark l;
  l.T_world_landmark = cascade.T;
  l.position_var = cascade.position_var;
  l.rotation_var = cascade.rotation_var;
  l.last_seen = t;
  if (surveyed != nullptr) {
    Landmark s;
    s.T_world_landmark = surveyed->T;
    s.position_var = surveyed->position_var;
    s.rotation_var = surveyed->rotation_var;
    s.fuse(cascade);
    l.T_world_landmark = s.T_world_landmark;
    l.position_var = s.position_var;
    l.rotation_var = s.rotation_var;
  }
  return l;
}

}  // namespace labo::estimation
