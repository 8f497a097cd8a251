#include "drone/sim/quadrotor_dynamics.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::sim {

namespace {
double clamp_unit(double v) { return std::isfinite(v) ? std::clamp(v, -1.0, 1.0) : 0.0; }
constexpr double kTouchdown_m = 1e-3;
// During the spin-up the motors reach this share of the hover thrust: the drone stays on the ground.
constexpr double kSpinupShare = 0.8;
}  // namespace

int to_control_state(FirmwarePhase phase) {
  switch (phase) {
    case FirmwarePhase::Landed: return labo::control_state::kLanded;
    case FirmwarePhase::TakingOff: return labo::control_state::kTakingOff;
    case FirmwarePhase::Flying: return labo::control_state::kFlying;
    case FirmwarePhase::Hovering: return labo::control_state::kHovering;
    case FirmwarePhase::Landing: return labo::control_state::kLanding;
    case FirmwarePhase::Emergency: return labo::control_state::kLanded;
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

AirframeParams deviated_airframe(const QuadrotorParams& p) {
  AirframeParams a = p.airframe;
  a.mass_kg *= p.deviation.mass_factor;
  a.inertia_kgm2 *= p.deviation.mass_factor;
  a.rotor_drag_per_s *= p.deviation.rotor_drag_factor;
  a.air_drag_kg_per_m *= p.deviation.air_drag_factor;
  return a;
}

RotorParams deviated_rotors(const QuadrotorParams& p) {
  RotorParams r = p.rotors;
  r.lag_s *= p.deviation.motor_lag_factor;
  for (std::size_t i = 0; i < r.efficiency.size(); ++i) r.efficiency[i] *= p.deviation.rotor_efficiency[i];
  return r;
}

FirmwareLoopParams deviated_loops(const QuadrotorParams& p) {
  FirmwareLoopParams l = p.loops;
  l.attitude_loop_per_s /= p.deviation.attitude_lag_factor;
  l.yaw_rate_loop_per_s /= p.deviation.yaw_lag_factor;
  l.vz_reference_per_s /= p.deviation.vertical_lag_factor;
  return l;
}

QuadrotorDynamics::QuadrotorDynamics(QuadrotorParams params, CollisionModel collision, const Eigen::Isometry3d& T_world_start)
    : p_(params),
      airframe_(deviated_airframe(p_)),
      propulsion_(deviated_rotors(p_), p_.battery),
      loops_(deviated_loops(p_), p_.airframe, p_.rotors),
      collision_(std::move(collision)) {
  // The firmware's height PD feeds its vertical-speed loop, whose shaping it designs for as a lag L:
  // vz' = L·(vz_ref − vz) with vz_ref = kp·e − kd·vz gives s² + L(1 + kd)s + L·kp: place its poles.
  const double L = p_.loops.vz_reference_per_s, w = p_.height_hold_bandwidth_radps;
  height_kp_ = w * w / L;
  height_kd_ = std::max(0.0, 2.0 * p_.height_hold_damping * w / L - 1.0);
  body_.position_m = T_world_start.translation();
  body_.attitude = Eigen::Quaterniond(Eigen::AngleAxisd(ypr_from_rotation(T_world_start.linear())[0], Eigen::Vector3d::UnitZ()));
  refresh_state(body_.velocity_mps);
  s_.acceleration_mps2.setZero();
}

// ---- commands ----------------------------------------------------------------------------------

void QuadrotorDynamics::takeoff() {
  if (s_.phase != FirmwarePhase::Landed || s_.battery_percent <= 0) return;
  s_.phase = FirmwarePhase::TakingOff;
  phase_start_t_ = s_.t;
  takeoff_target_z_ = collision_.support_height(s_.position_m) + p_.takeoff_height_m;
  loops_.reset();
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
    propulsion_.stop();
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
  body_.velocity_mps += dv_world_mps;
  body_.attitude = (Eigen::Quaterniond(Eigen::AngleAxisd(dyaw_rad, Eigen::Vector3d::UnitZ())) * body_.attitude).normalized();
  const Eigen::Vector3d a = s_.acceleration_mps2;
  refresh_state(body_.velocity_mps);
  s_.acceleration_mps2 = a;
}

// ---- one step ----------------------------------------------------------------------------------

void QuadrotorDynamics::step() {
  s_.t = static_cast<double>(++steps_) * p_.step_s;  // no accumulated rounding
  update_phase();
  if (s_.phase == FirmwarePhase::Landed) {
    propulsion_.stop();
    s_.acceleration_mps2.setZero();
    s_.angular_velocity_body_radps.setZero();
  } else if (s_.phase == FirmwarePhase::Emergency) {
    fall();
  } else {
    fly();
    contact_and_collisions();
  }
  propulsion_.drain(s_.airborne(), p_.step_s);
  s_.battery_percent = propulsion_.charge_percent();
  s_.battery_voltage_v = propulsion_.voltage_v();
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

FirmwareSetpoints QuadrotorDynamics::firmware_hover_targets() const {
  FirmwareSetpoints t;
  if (!velocity_observable_) return t;  // blind: level out and drift
  const double c = std::cos(s_.yaw_rad), s = std::sin(s_.yaw_rad);
  const Eigen::Vector3d& v = s_.velocity_mps;
  const double forward = c * v.x() + s * v.y(), left = -s * v.x() + c * v.y();
  const double k = p_.hover_velocity_gain_per_s / p_.airframe.gravity_mps2;
  t.pitch_rad = std::clamp(std::atan(-k * forward), -p_.tilt_max_rad, p_.tilt_max_rad);  // nose down = forward
  t.roll_rad = std::clamp(std::atan(k * left), -p_.tilt_max_rad, p_.tilt_max_rad);       // right side down = right
  return t;
}

double QuadrotorDynamics::height_hold_vz(double target_z) const {
  const double vz = height_kp_ * (target_z - s_.position_m.z()) - height_kd_ * s_.velocity_mps.z();
  return std::clamp(vz, -p_.vz_max_mps, p_.vz_max_mps);
}

FirmwareSetpoints QuadrotorDynamics::targets() {
  FirmwareSetpoints t;
  switch (s_.phase) {
    case FirmwarePhase::TakingOff:
      t = firmware_hover_targets();
      t.vz_mps = height_hold_vz(takeoff_target_z_);
      return t;
    case FirmwarePhase::Landing:
      t = firmware_hover_targets();
      t.vz_mps = -p_.landing_speed_mps;
      return t;
    case FirmwarePhase::Hovering:
      t = firmware_hover_targets();
      t.vz_mps = height_hold_vz(hold_z_);
      break;
    default:
      t.roll_rad = command_.roll * p_.tilt_max_rad;
      t.pitch_rad = command_.pitch * p_.tilt_max_rad;
      t.yaw_rate_radps = command_.yaw_rate * p_.yaw_rate_max_radps;
      t.vz_mps = command_.gaz * p_.vz_max_mps;
      break;
  }
  // The firmware's altitude window, measured above the surface below.
  const double surface = s_.position_m.z() - height_above_surface();
  t.vz_mps = std::min(t.vz_mps, height_hold_vz(surface + p_.altitude_max_m));
  t.vz_mps = std::max(t.vz_mps, height_hold_vz(surface + p_.altitude_min_m));
  return t;
}

void QuadrotorDynamics::fly() {
  const FirmwareSetpoints set = targets();
  RotorThrusts demand{};
  if (s_.phase == FirmwarePhase::TakingOff && s_.t - phase_start_t_ < p_.takeoff_spinup_s) {
    demand.fill(kSpinupShare * p_.airframe.mass_kg * p_.airframe.gravity_mps2 / 4.0);
    loops_.reset();
  } else {
    FirmwareSensing sensed;
    sensed.roll_rad = s_.roll_rad + p_.deviation.attitude_bias_rad.x();
    sensed.pitch_rad = s_.pitch_rad + p_.deviation.attitude_bias_rad.y();
    sensed.rates_body_radps = body_.rates_body_radps;
    sensed.vz_mps = body_.velocity_mps.z();
    demand = loops_.update(set, sensed, p_.step_s);
  }
  const Eigen::Vector3d v_before = body_.velocity_mps;
  const Seconds h = p_.step_s / p_.substeps;
  for (int i = 0; i < p_.substeps; ++i) {
    const double support = collision_.support_height(body_.position_m);
    propulsion_.step(demand, true, h);
    airframe_.step(body_, propulsion_.thrust(), wind_, body_.position_m.z() - support, h);
    if (body_.position_m.z() <= support && body_.velocity_mps.z() <= 0) rest_on(support);  // pressed onto it
  }
  refresh_state(v_before);
}

// The drone sits on a surface: level, still, at its current heading.
void QuadrotorDynamics::rest_on(double support) {
  body_.position_m.z() = support;
  body_.velocity_mps.setZero();
  body_.rates_body_radps.setZero();
  const double yaw = ypr_from_rotation(body_.attitude.toRotationMatrix())[0];
  body_.attitude = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
}

void QuadrotorDynamics::refresh_state(const Eigen::Vector3d& v_before) {
  s_.position_m = body_.position_m;
  s_.velocity_mps = body_.velocity_mps;
  s_.acceleration_mps2 = (body_.velocity_mps - v_before) / p_.step_s;
  const Eigen::Vector3d ypr = ypr_from_rotation(body_.attitude.toRotationMatrix());
  s_.yaw_rad = ypr[0];
  s_.pitch_rad = ypr[1];
  s_.roll_rad = ypr[2];
  const Eigen::Vector3d& w = body_.rates_body_radps;
  s_.angular_velocity_body_radps = w;
  s_.yaw_rate_radps = (w.y() * std::sin(s_.roll_rad) + w.z() * std::cos(s_.roll_rad)) / std::cos(s_.pitch_rad);
}

void QuadrotorDynamics::contact_and_collisions() {
  if (auto hit = collision_.obstacle_hit(s_.position_m)) {
    s_.phase = FirmwarePhase::Emergency;
    s_.crash_reason = *hit;
    ++s_.crashes;
    holding_ = false;
    propulsion_.stop();
    body_.velocity_mps.head<2>().setZero();  // stopped by what it hit; then it falls
    s_.velocity_mps = body_.velocity_mps;
    return;
  }
  const double support = collision_.support_height(s_.position_m);
  if (s_.phase == FirmwarePhase::Landing && s_.position_m.z() <= support + kTouchdown_m) {
    s_.phase = FirmwarePhase::Landed;
    rest_on(support);
    propulsion_.stop();
    loops_.reset();
    refresh_state(body_.velocity_mps);
    s_.acceleration_mps2.setZero();
  }
}

void QuadrotorDynamics::fall() {
  const Seconds dt = p_.step_s;
  const double support = collision_.support_height(body_.position_m);
  if (body_.position_m.z() <= support + kTouchdown_m && body_.velocity_mps.norm() < 1e-6) {
    s_.acceleration_mps2.setZero();
    return;
  }
  const Eigen::Vector3d v0 = body_.velocity_mps;
  const AirframeParams& a = airframe_.params();
  body_.velocity_mps += (-a.air_drag_kg_per_m / a.mass_kg * v0.norm() * v0 - Eigen::Vector3d(0, 0, a.gravity_mps2)) * dt;
  body_.position_m += 0.5 * (v0 + body_.velocity_mps) * dt;
  body_.rates_body_radps.setZero();
  if (body_.position_m.z() <= support) rest_on(support);  // lies on the ground, level
  refresh_state(v0);
  if (body_.velocity_mps.isZero()) s_.acceleration_mps2.setZero();
}

double QuadrotorDynamics::height_above_surface() const {
  return s_.position_m.z() - collision_.support_height(s_.position_m);
}

}  // namespace labo::sim
