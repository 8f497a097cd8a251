#include "control/estimate_correction.hpp"

namespace labo::control {

Eigen::Vector3d EstimateCorrection::update(const fusion::PoseEstimate& pose, Seconds t) {
  if (!pose.valid) {
    have_last_ = false;
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d p = pose.T_world_body.translation();
  Eigen::Vector3d correction = Eigen::Vector3d::Zero();
  // The velocity's trapezoid over the tick is the motion; the rest of the displacement is the fix.
  if (have_last_ && t > last_t_) correction = p - last_position_ - 0.5 * (last_velocity_ + pose.velocity_world) * (t - last_t_);
  have_last_ = true;
  last_t_ = t;
  last_position_ = p;
  last_velocity_ = pose.velocity_world;
  return correction;
}

}  // namespace labo::control
