#include "control/pid_controller.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kOpposingUnwindFactor = 2.5;
// A set point moving slower than this is still for the xy integral (a face followed, a leg flown
// move it faster).
constexpr double kStillSetPointMps = 0.05;
}

double PidAxis::unclipped(double error, double rate) const {
  return gains_.kp * error + gains_.ki * integral_ - gains_.kd * rate;
}

void PidAxis::integrate(double error, double dt, bool saturated_in_error_direction, bool accumulate) {
  if (gains_.ki <= 0 || gains_.integral_limit <= 0 || dt <= 0) return;
  const bool opposes = integral_ * error < 0;
  if (opposes) {
    // Unwind faster, but stop at zero: the sign of the integral only changes by ordinary integration.
    const double next = integral_ + kOpposingUnwindFactor * error * dt;
    integral_ = (next * integral_ < 0) ? 0.0 : next;
    return;
  }
  if (saturated_in_error_direction || !accumulate) return;  // conditional integration: no windup at the limit
  integral_ = std::clamp(integral_ + error * dt, -gains_.integral_limit, gains_.integral_limit);
}

double PidAxis::update(double error, double rate, double dt) {
  const double raw = unclipped(error, rate);
  const bool saturated = (raw >= gains_.out_max && error > 0) || (raw <= gains_.out_min && error < 0);
  integrate(error, dt, saturated, in_zone(error));
  return std::clamp(unclipped(error, rate), gains_.out_min, gains_.out_max);
}

Eigen::Vector2d world_to_body_xy(const Eigen::Vector2d& v_world, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * v_world.x() + s * v_world.y(), -s * v_world.x() + c * v_world.y()};
}

PoseController::PoseController(const PoseControlGains& gains)
    : gains_(gains), x_(gains.xy), y_(gains.xy), z_(gains.z), yaw_(gains.yaw) {}

void PoseController::set_target(const PoseTarget& target, bool keep_state) {
  const bool changed = (target.position - target_.position).norm() > 1e-9 ||
                       std::abs(wrap_angle(target.yaw - target_.yaw)) > 1e-9;
  target_ = target;
  if (changed && !keep_state) reset();
}

void PoseController::reset() {
  x_.reset();
  y_.reset();
  z_.reset();
  yaw_.reset();
}

MoveCommand PoseController::update(const fusion::PoseEstimate& pose, double dt) {
  const Eigen::Vector3d p = pose.T_world_body.translation();
  const double yaw = ypr_from_rotation(pose.T_world_body.linear())[0];
  const Eigen::Vector3d e = target_.position - p;
  // Relative velocity: the derivative damps motion relative to a moving set point.
  const Eigen::Vector3d v = pose.velocity_world - target_.velocity;
  const Eigen::Vector2d feed_forward = gains_.xy_velocity_feedforward * target_.velocity.head<2>();

  // Horizontal: world-frame PID pair, jointly clipped to the tilt limit (direction kept), then rotated.
  const Eigen::Vector2d raw = Eigen::Vector2d(x_.unclipped(e.x(), v.x()), y_.unclipped(e.y(), v.y())) + feed_forward;
  const double limit = gains_.max_tilt_command;
  const bool saturated = raw.norm() >= limit;
  const bool near_still_set_point = x_.in_zone(e.head<2>().norm()) && target_.velocity.head<2>().norm() < kStillSetPointMps;
  x_.integrate(e.x(), dt, saturated && raw.x() * e.x() > 0, near_still_set_point);
  y_.integrate(e.y(), dt, saturated && raw.y() * e.y() > 0, near_still_set_point);
  Eigen::Vector2d u = Eigen::Vector2d(x_.unclipped(e.x(), v.x()), y_.unclipped(e.y(), v.y())) + feed_forward;
  if (u.norm() > limit) u *= limit / u.norm();
  const Eigen::Vector2d u_body = world_to_body_xy(u, yaw);

  MoveCommand cmd;
  cmd.pitch = u_body.x();   // > 0: nose down, forward
  cmd.roll = -u_body.y();   // > 0: right, i.e. towards -y (body y is left)
  cmd.gaz = z_.update(e.z(), v.z(), dt);
  const double yaw_feed_forward = gains_.yaw_rate_feedforward * target_.yaw_rate;
  cmd.yaw_rate = std::clamp(yaw_.update(wrap_angle(target_.yaw - yaw), pose.yaw_rate - target_.yaw_rate, dt) + yaw_feed_forward,
                            gains_.yaw.out_min, gains_.yaw.out_max);
  return cmd;
}

}  // namespace labo::control
