#include "control/autopilot.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"
#include "drone/drone_link.hpp"

namespace labo::control {

namespace {
constexpr double kMaxControlDt = 0.2;  // a longer gap (stall, first tick) is not integrated

FlightOutput action(FlightOutput::Action a) {
  FlightOutput out;
  out.action = a;
  return out;
}
}  // namespace

Autopilot::Autopilot(const ControlConfig& config, Geofence fence)
    : config_(config), fence_(std::move(fence)), controller_(config.gains) {}

FlightOutput Autopilot::takeoff(Seconds t) {
  phase_ = FlightPhase::TakingOff;
  phase_since_ = t;
  target_.reset();
  controller_.reset();
  return action(FlightOutput::Action::Takeoff);
}

FlightOutput Autopilot::land(Seconds t) {
  if (phase_ != FlightPhase::Landed && phase_ != FlightPhase::Emergency) {
    phase_ = FlightPhase::Landing;
    phase_since_ = t;
  }
  target_.reset();
  return action(FlightOutput::Action::Land);
}

FlightOutput Autopilot::emergency(Seconds t) {
  phase_ = FlightPhase::Emergency;
  phase_since_ = t;
  target_.reset();
  return action(FlightOutput::Action::Emergency);
}

void Autopilot::on_control_state(int control_state, Seconds t) {
  const bool airborne = control_state == control_state::kFlying || control_state == control_state::kHovering;
  switch (phase_) {
    case FlightPhase::TakingOff:
      if (airborne || t - phase_since_ > config_.autopilot.takeoff_time_s) {
        phase_ = FlightPhase::Flying;
        phase_since_ = t;
      }
      break;
    case FlightPhase::Landing:
      if (control_state == control_state::kLanded || t - phase_since_ > config_.autopilot.land_time_s) {
        phase_ = FlightPhase::Landed;
        phase_since_ = t;
      }
      break;
    case FlightPhase::Emergency:
      // Motors cut; the drone is on the floor once it reports landed again.
      if (control_state == control_state::kLanded && t - phase_since_ > 1.0) phase_ = FlightPhase::Landed;
      break;
    case FlightPhase::Landed:
    case FlightPhase::Flying:
      break;
  }
}

void Autopilot::go_to(const PoseTarget& target, Seconds t, bool new_waypoint) {
  PoseTarget clamped = target;
  clamped.position = fence_.clamp(target.position);
  clamped.yaw = wrap_angle(target.yaw);
  if (new_waypoint || !target_) {
    controller_.set_target(clamped);
    reached_ = false;
    done_ = false;
    within_since_ = -1;
  } else {
    controller_.set_target(clamped, /*keep_state=*/true);  // moving set point: keep the integrals
  }
  (void)t;
  target_ = clamped;
}

void Autopilot::hold_here(const fusion::PoseEstimate& pose, Seconds t) {
  go_to({pose.T_world_body.translation(), ypr_from_rotation(pose.T_world_body.linear())[0]}, t);
}

void Autopilot::update_criteria(const fusion::PoseEstimate& pose, Seconds t) {
  const double yaw = ypr_from_rotation(pose.T_world_body.linear())[0];
  distance_ = (target_->position - pose.T_world_body.translation()).norm();
  const double yaw_error = std::abs(wrap_angle(target_->yaw - yaw));
  const auto& c = config_.autopilot;
  if (!reached_ && distance_ < c.reach_distance_m && yaw_error < c.reach_yaw_rad) reached_ = true;
  if (!reached_) return;
  if (distance_ < c.stay_distance_m) {
    if (within_since_ < 0) within_since_ = t;
    if (t - within_since_ >= c.stay_time_s) done_ = true;
  } else {
    within_since_ = -1;
  }
}

FlightOutput Autopilot::step(const fusion::PoseEstimate& pose, Seconds t) {
  const double dt = (last_step_t_ < 0) ? 0.0 : std::clamp(t - last_step_t_, 0.0, kMaxControlDt);
  last_step_t_ = t;
  FlightOutput out;
  if (phase_ != FlightPhase::Flying) {
    out.action = FlightOutput::Action::None;
    return out;
  }
  if (target_ && pose.valid) {
    update_criteria(pose, t);
    out.action = FlightOutput::Action::Move;
    out.move = controller_.update(pose, dt);
  } else {
    out.action = FlightOutput::Action::Hover;
  }
  last_command_ = out.action == FlightOutput::Action::Move ? out.move : MoveCommand{};
  return out;
}

}  // namespace labo::control
