#include "drone/sim/quadrotor_dynamics.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo {

namespace {
// The exact one-step factor of a first-order lag x' = rate·(ref − x).
double lag_factor(double rate_per_s, Seconds dt) { return 1.0 - std::exp(-rate_per_s * dt); }
double clamp_unit(double v) { return std::isfinite(v) ? std::clamp(v, -1.0, 1.0) : 0.0; }
constexpr double kTouchdown_m = 1e-3;
}  // namespace

int control_state(FirmwarePhase phase) {
  switch (phase) {
    case FirmwarePhase::Landed: return 2;
    case FirmwarePhase::TakingOff: return 6;
    case FirmwarePhase::Flying: return 3;
    case FirmwarePhase::Hovering: return 4;
    case FirmwarePhase::Landing: return 8;
    case FirmwarePhase::Emergency: return 2;
  }
  return 0;
}

std::string to_string(FirmwarePhase phase) {
  switch (phase) {
    case FirmwarePhase::Landed: return "landed";
    case FirmwarePhase::TakingOff: return "taking off";
    case FirmwarePhase::Flying: return "flying";
    case FirmwarePhase::Hovering: return "hovering";
    case FirmwarePhase::Landing: return "landing";
    case FirmwarePhase::Emergency: return "emergency";
  }
  return "?";
}

Eigen::Isometry3d QuadrotorState::T_world_body() const { return make_pose(position_m, yaw_rad, pitch_rad, roll_rad); }

bool QuadrotorState::airborne() const {
  return phase == FirmwarePhase::TakingOff || phase == FirmwarePhase::Flying || phase == FirmwarePhase::Hovering ||
         phase == FirmwarePhase::Landing;
}

QuadrotorDynamics::QuadrotorDynamics(QuadrotorParams params, CollisionModel collision,
                                     const Eigen::Isometry3d& T_world_start)
    : p_(params),
      collision_(std::move(collision)),
      attitude_alpha_(lag_factor(p_.attitude_rate_per_s, p_.step_s)),
      yaw_alpha_(lag_factor(p_.yaw_response_per_s, p_.step_s)),
      vertical_alpha_(lag_factor(p_.vertical_response_per_s, p_.step_s)) {
  // vz' = L·(vz_ref − vz) with vz_ref = kp·e − kd·vz gives s² + L(1 + kd)s + L·kp: place its poles.
  const double L = p_.vertical_response_per_s, w = p_.height_hold_bandwidth_radps;
  height_kp_ = w * w / L;
  height_kd_ = std::max(0.0, 2.0 * p_.height_hold_damping * w / L - 1.0);
  s_.position_m = T_world_start.translation();
  s_.yaw_rad = ypr_from_rotation(T_world_start.linear())[0];
  s_.battery_percent = p_.battery_start_percent;
}

// ---- commands ----------------------------------------------------------------------------------

void QuadrotorDynamics::takeoff() {
  if (s_.phase != FirmwarePhase::Landed || s_.battery_percent <= 0) return;
  s_.phase = FirmwarePhase::TakingOff;
  phase_start_t_ = s_.t;
  takeoff_target_z_ = collision_.support_height(s_.position_m) + p_.takeoff_height_m;
}

void QuadrotorDynamics::land() {
  if (s_.phase == FirmwarePhase::TakingOff || s_.phase == FirmwarePhase::Flying || s_.phase == FirmwarePhase::Hovering) {
    s_.phase = FirmwarePhase::Landing;
    holding_ = false;
  }
}

void QuadrotorDynamics::emergency() {
  if (s_.phase != FirmwarePhase::Emergency) {
    s_.phase = FirmwarePhase::Emergency;  // motors cut at once
    holding_ = false;
    return;
  }
  // The toggle clears an emergency once the drone lies on the ground.
  if (s_.position_m.z() <= collision_.support_height(s_.position_m) + kTouchdown_m && s_.velocity_mps.norm() < 1e-6) {
    s_.phase = FirmwarePhase::Landed;
    s_.crash_reason.clear();
  }
}

void QuadrotorDynamics::move(const MoveCommand& c, bool hover) {
  command_ = {clamp_unit(c.roll), clamp_unit(c.pitch), clamp_unit(c.gaz), clamp_unit(c.yaw_rate)};
  hover_flag_ = hover;
  last_command_t_ = s_.t;
}

void QuadrotorDynamics::push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad) {
  if (!s_.airborne()) return;
  s_.velocity_mps += dv_world_mps;
  // The yaw-rate kick that the discrete lag (factor a per step, applied before integrating) turns
  // into exactly dyaw: sum over k >= 1 of kick·(1 − a)^k·dt = kick·dt·(1 − a)/a.
  s_.yaw_rate_radps += dyaw_rad * yaw_alpha_ / ((1.0 - yaw_alpha_) * p_.step_s);
}

// ---- one step ----------------------------------------------------------------------------------

void QuadrotorDynamics::step() {
  s_.t = static_cast<double>(++steps_) * p_.step_s;  // no accumulated rounding
  update_phase();
  if (s_.phase == FirmwarePhase::Landed) {
    s_.acceleration_mps2.setZero();
    s_.angular_velocity_body_radps.setZero();
  } else if (s_.phase == FirmwarePhase::Emergency) {
    fall();
  } else {
    integrate(targets());
    contact_and_collisions();
  }
  drain_battery();
}

void QuadrotorDynamics::update_phase() {
  switch (s_.phase) {
    case FirmwarePhase::TakingOff:
      if (s_.t - phase_start_t_ >= p_.takeoff_spinup_s && s_.position_m.z() >= takeoff_target_z_ - 0.05 &&
          std::abs(s_.velocity_mps.z()) < 0.1) {
        s_.phase = FirmwarePhase::Hovering;
        hold_z_ = takeoff_target_z_;
        holding_ = true;
      }
      break;
    case FirmwarePhase::Flying:
    case FirmwarePhase::Hovering: {
      const bool hover = hover_flag_ || s_.t - last_command_t_ > p_.command_timeout_s;
      if (hover && !holding_) hold_z_ = s_.position_m.z();
      holding_ = hover;
      s_.phase = hover ? FirmwarePhase::Hovering : FirmwarePhase::Flying;
      if (s_.battery_percent <= 0) s_.phase = FirmwarePhase::Landing;  // the firmware lands on an empty battery
      break;
    }
    default: break;
  }
  s_.hovering_by_firmware = s_.phase == FirmwarePhase::Hovering;
}

QuadrotorDynamics::Targets QuadrotorDynamics::firmware_hover_targets() const {
  Targets t;
  if (!velocity_observable_) return t;  // blind: level out and drift
  const double c = std::cos(s_.yaw_rad), s = std::sin(s_.yaw_rad);
  const Eigen::Vector3d& v = s_.velocity_mps;
  const double forward = c * v.x() + s * v.y(), left = -s * v.x() + c * v.y();
  const double k = p_.hover_velocity_gain_per_s / p_.gravity_mps2;
  t.pitch = std::clamp(std::atan(-k * forward), -p_.tilt_max_rad, p_.tilt_max_rad);  // nose down = forward
  t.roll = std::clamp(std::atan(k * left), -p_.tilt_max_rad, p_.tilt_max_rad);       // right side down = right
  return t;
}

double QuadrotorDynamics::height_hold_vz(double target_z) const {
  const double vz = height_kp_ * (target_z - s_.position_m.z()) - height_kd_ * s_.velocity_mps.z();
  return std::clamp(vz, -p_.vz_max_mps, p_.vz_max_mps);
}

QuadrotorDynamics::Targets QuadrotorDynamics::targets() {
  Targets t;
  switch (s_.phase) {
    case FirmwarePhase::TakingOff:
      t = firmware_hover_targets();
      if (s_.t - phase_start_t_ >= p_.takeoff_spinup_s) t.vz = height_hold_vz(takeoff_target_z_);
      return t;
    case FirmwarePhase::Landing:
      t = firmware_hover_targets();
      t.vz = -p_.landing_speed_mps;
      return t;
    case FirmwarePhase::Hovering:
      t = firmware_hover_targets();
      t.vz = height_hold_vz(hold_z_);
      break;
    default:
      t.roll = command_.roll * p_.tilt_max_rad;
      t.pitch = command_.pitch * p_.tilt_max_rad;
      t.yaw_rate = command_.yaw_rate * p_.yaw_rate_max_radps;
      t.vz = command_.gaz * p_.vz_max_mps;
      break;
  }
  // The firmware's altitude window, measured above the surface below.
  const double surface = s_.position_m.z() - height_above_surface();
  t.vz = std::min(t.vz, height_hold_vz(surface + p_.altitude_max_m));
  t.vz = std::max(t.vz, height_hold_vz(surface + p_.altitude_min_m));
  return t;
}

void QuadrotorDynamics::integrate(const Targets& ref) {
  const double dt = p_.step_s;
  const double roll0 = s_.roll_rad, pitch0 = s_.pitch_rad;
  s_.roll_rad += attitude_alpha_ * (ref.roll - s_.roll_rad);
  s_.pitch_rad += attitude_alpha_ * (ref.pitch - s_.pitch_rad);
  double& yaw_rate = s_.yaw_rate_radps;
  yaw_rate += yaw_alpha_ * (ref.yaw_rate - yaw_rate);
  s_.yaw_rad = wrap_angle(s_.yaw_rad + yaw_rate * dt);

  const Eigen::Vector3d v0 = s_.velocity_mps;
  Eigen::Vector3d v1 = v0;
  v1.z() += vertical_alpha_ * (ref.vz - v0.z());
  // The thrust carries the weight; its tilt accelerates horizontally.
  const Eigen::Vector3d thrust_dir = rotation_from_ypr(s_.yaw_rad, s_.pitch_rad, s_.roll_rad).col(2);
  const Eigen::Vector2d a_h = p_.gravity_mps2 * thrust_dir.head<2>() / thrust_dir.z() -
                              p_.drag_per_s * (v0.head<2>() - wind_.head<2>());
  v1.head<2>() += a_h * dt;
  s_.position_m += 0.5 * (v0 + v1) * dt;
  s_.velocity_mps = v1;
  s_.acceleration_mps2 = (v1 - v0) / dt;

  // Body rates from the Euler-angle rates (Z-Y-X), for the gyroscopes and motion blur.
  const double droll = (s_.roll_rad - roll0) / dt, dpitch = (s_.pitch_rad - pitch0) / dt, dyaw = yaw_rate;
  const double sr = std::sin(s_.roll_rad), cr = std::cos(s_.roll_rad);
  const double sp = std::sin(s_.pitch_rad), cp = std::cos(s_.pitch_rad);
  s_.angular_velocity_body_radps = Eigen::Vector3d(droll - dyaw * sp, dpitch * cr + dyaw * cp * sr, -dpitch * sr + dyaw * cp * cr);
}

void QuadrotorDynamics::contact_and_collisions() {
  if (auto hit = collision_.obstacle_hit(s_.position_m)) {
    s_.phase = FirmwarePhase::Emergency;
    s_.crash_reason = *hit;
    ++s_.crashes;
    holding_ = false;
    s_.velocity_mps.head<2>().setZero();  // stopped by what it hit; then it falls
    return;
  }
  const double support = collision_.support_height(s_.position_m);
  if (s_.position_m.z() <= support + kTouchdown_m) {
    s_.position_m.z() = std::max(s_.position_m.z(), support);
    if (s_.velocity_mps.z() < 0) s_.velocity_mps.z() = 0;
    if (s_.phase == FirmwarePhase::Landing) {
      s_.phase = FirmwarePhase::Landed;
      s_.position_m.z() = support;
      s_.velocity_mps.setZero();
      s_.roll_rad = s_.pitch_rad = s_.yaw_rate_radps = 0;
      s_.angular_velocity_body_radps.setZero();
    }
  }
}

void QuadrotorDynamics::fall() {
  const double dt = p_.step_s;
  const double support = collision_.support_height(s_.position_m);
  if (s_.position_m.z() <= support + kTouchdown_m && s_.velocity_mps.norm() < 1e-6) {
    s_.acceleration_mps2.setZero();
    return;
  }
  const Eigen::Vector3d v0 = s_.velocity_mps;
  s_.velocity_mps.z() -= p_.gravity_mps2 * dt;
  s_.velocity_mps.head<2>() *= 1.0 - std::min(1.0, p_.drag_per_s * dt);
  s_.position_m += 0.5 * (v0 + s_.velocity_mps) * dt;
  s_.acceleration_mps2 = (s_.velocity_mps - v0) / dt;
  if (s_.position_m.z() <= support) {  // lies on the ground, level
    s_.position_m.z() = support;
    s_.velocity_mps.setZero();
    s_.acceleration_mps2.setZero();
    s_.roll_rad = s_.pitch_rad = s_.yaw_rate_radps = 0;
    s_.angular_velocity_body_radps.setZero();
  }
}

void QuadrotorDynamics::drain_battery() {
  const double rate = s_.airborne() ? p_.battery_flying_drain_percent_per_s : p_.battery_idle_drain_percent_per_s;
  s_.battery_percent = std::max(0.0, s_.battery_percent - rate * p_.step_s);
}

double QuadrotorDynamics::height_above_surface() const {
  return s_.position_m.z() - collision_.support_height(s_.position_m);
}

}  // namespace labo
