#include "localization/estimation/vision_gate.hpp"

#include <cmath>

#include "core/frames.hpp"

namespace labo::estimation {

VisionGate::Verdict VisionGate::check(const Eigen::Isometry3d& T_world_body, Seconds t, double max_distance_m,
                                      double max_angle_rad) {
  Verdict v = Verdict::Consistent;
  if (has_previous_ && t - previous_t_ <= kWindow) {
    const Eigen::Isometry3d delta = previous_.inverse() * T_world_body;
    const Eigen::Vector3d ypr = ypr_from_rotation(delta.linear());
    if (delta.translation().norm() > max_distance_m) {
      v = Verdict::JumpDistance;
    } else if (ypr.cwiseAbs().maxCoeff() > max_angle_rad) {
      v = Verdict::JumpAngle;
    }
  }
  has_previous_ = true;
  previous_t_ = t;
  previous_ = T_world_body;
  return v;
}

}  // namespace labo::estimation
