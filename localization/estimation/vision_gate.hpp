#pragma once
// VisionGate: the paper's tracking-loss test (§4.1): a visual pose that moved by more than D, or
// turned by more than beta about any axis, since the previous frame of the same source is refused.
// Frames further apart than `window` are not compared (the source was lost in between).
#include <Eigen/Geometry>

#include "core/time.hpp"

namespace labo::estimation {

class VisionGate {
 public:
  enum class Verdict { Consistent, JumpDistance, JumpAngle };
  static constexpr Seconds kWindow = 0.5;

  // Compares with the previous frame and remembers this one (a jumped frame becomes the reference, so
  // a tracker that re-locks elsewhere is accepted again after the settling frames).
  Verdict check(const Eigen::Isometry3d& T_world_body, Seconds t, double max_distance_m, double max_angle_rad);

 private:
  bool has_previous_ = false;
  Seconds previous_t_ = 0;
  Eigen::Isometry3d previous_ = Eigen::Isometry3d::Identity();
};

}  // namespace labo::estimation
