#pragma once
// PID control of x, y, z and yaw on the filter's predicted pose (notes/tum_ardrone.md §4, with its
// caveats fixed): errors in the world frame, derivative from the estimated velocity (not a
// differentiated error, so a new target causes no derivative kick), integral with anti-windup (capped,
// frozen while the output saturates in the error's direction, unwound 2.5x faster when the error
// opposes it, never pushed across zero by that unwinding) and reset on every new target. The x/y
// outputs are computed in the world frame - integral included - and rotated into the body frame, so
// the integral stays consistent while the drone turns. Outputs are clipped to the PCMD range.
#include <Eigen/Core>

#include <cmath>

#include "control/control_config.hpp"
#include "localization/fusion/localization_pipelines.hpp"
#include "drone/drone_link.hpp"

namespace labo::control {

class PidAxis {
 public:
  explicit PidAxis(const PidGains& gains) : gains_(gains) {}
  // error = target - state; rate = d(state)/dt from the filter; returns the clipped output.
  double update(double error, double rate, double dt);
  // Unclipped output for a given integral state (used by the x/y pair before the joint clip).
  double unclipped(double error, double rate) const;
  // The integral follows the error unless saturated in its direction or told not to accumulate; it
  // always unwinds when the error opposes it.
  void integrate(double error, double dt, bool saturated_in_error_direction, bool accumulate = true);
  // Whether an error of this magnitude lies in the integral's zone (gains' integral_zone, 0: any).
  bool in_zone(double error_magnitude) const {
    return gains_.integral_zone <= 0 || std::abs(error_magnitude) <= gains_.integral_zone;
  }
  void reset() { integral_ = 0; }
  double integral() const { return integral_; }
  const PidGains& gains() const { return gains_; }

 private:
  PidGains gains_;
  double integral_ = 0;
};

// Target pose for the controller: world position and yaw.
struct PoseTarget {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0;
  // A moving set point's velocity (world): the derivative acts on (target velocity - velocity) and
  // the horizontal command gets a feed-forward tilt for it, so a followed target is not lagged.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  // A turning set point's yaw rate (rad/s), fed forward the same way.
  double yaw_rate = 0;
};

class PoseController {
 public:
  explicit PoseController(const PoseControlGains& gains);
  // Sets a new target; resets every integral when it differs from the current one, unless keep_state
  // (a set point moving along a trajectory).
  void set_target(const PoseTarget& target, bool keep_state = false);
  const PoseTarget& target() const { return target_; }
  // The command that drives `pose` towards the target; dt is the time since the last call.
  MoveCommand update(const fusion::PoseEstimate& pose, double dt);
  void reset();

  const PidAxis& axis_x() const { return x_; }
  const PidAxis& axis_z() const { return z_; }

 private:
  PoseControlGains gains_;
  PoseTarget target_;
  PidAxis x_, y_, z_, yaw_;
};

// Rotates a world-frame horizontal vector into the body frame for a given yaw: (forward, left).
Eigen::Vector2d world_to_body_xy(const Eigen::Vector2d& v_world, double yaw);

}  // namespace labo::control
