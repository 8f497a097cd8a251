#include "localization/estimation/landmark.hpp"

#include <algorithm>

namespace labo {

void Landmark::blend(const Eigen::Isometry3d& T_measured, double k) {
  k = std::clamp(k, 0.0, 1.0);
  const Eigen::Quaterniond q0(T_world_landmark.linear()), q1(T_measured.linear());
  const Eigen::Vector3d t = (1.0 - k) * T_world_landmark.translation() + k * T_measured.translation();
  T_world_landmark.linear() = q0.slerp(k, q1).normalized().toRotationMatrix();
  T_world_landmark.translation() = t;
}

void Landmark::fuse(const Eigen::Isometry3d& T_measured, double var) {
  const double k = position_var / (position_var + var);
  blend(T_measured, k);
  position_var = (1.0 - k) * position_var;
  ++refinements;
}

Landmark place_landmark(const Eigen::Isometry3d& T_cascade, double cascade_var, const Eigen::Isometry3d* T_surveyed,
                        double survey_var, Seconds t) {
  Landmark l;
  l.T_world_landmark = T_cascade;
  l.position_var = cascade_var;
  l.last_seen = t;
  if (T_surveyed != nullptr) {
    Landmark surveyed;
    surveyed.T_world_landmark = *T_surveyed;
    surveyed.position_var = survey_var;
    surveyed.fuse(T_cascade, cascade_var);
    l.T_world_landmark = surveyed.T_world_landmark;
    l.position_var = surveyed.position_var;
  }
  return l;
}

}  // namespace labo
