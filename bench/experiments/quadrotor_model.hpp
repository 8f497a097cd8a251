#pragma once
// A small closed-loop model of the AR.Drone 2.0 (not the simulated lab of drone/sim/): attitude
// follows the PCMD tilt with a first-order lag, horizontal acceleration g*tan(tilt) against linear
// drag, vertical speed and yaw rate follow gaz and yaw_rate with lags, firmware take-off/landing and
// hover (brakes to zero velocity). Navdata like the real drone: body velocities, ultrasound height,
// control state, battery.
#include <algorithm>
#include <cmath>

#include "core/frames.hpp"
#include "drone/drone_link.hpp"

namespace labo::bench {

class QuadrotorModel {
 public:
  static constexpr double kMaxTilt = 0.21;      // rad (12 deg, euler_angle_max)
  static constexpr double kMaxVz = 0.7;         // m/s
  static constexpr double kMaxYawRate = 1.75;   // rad/s
  static constexpr double kDrag = 0.5;          // 1/s
  static constexpr double kG = 9.81;

  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  double yaw = 0, roll = 0, pitch = 0, yaw_rate = 0;
  int control_state = control_state::kLanded;
  double battery = 90;
  bool crashed = false;

  void takeoff() {
    if (control_state == control_state::kLanded) { control_state = control_state::kTakingOff; phase_t_ = 0; }
  }
  void land() {
    if (control_state != control_state::kLanded) { control_state = control_state::kLanding; }
  }
  // An external push (the paper's impulses): a velocity change in m/s, and a yaw-rate kick that turns
  // the drone by about `dyaw` rad before the onboard yaw-rate loop (0.2 s) absorbs it.
  void push(const Eigen::Vector3d& dv, double dyaw) {
    v += dv;
    yaw_rate += dyaw / 0.2;
  }
  void emergency() { control_state = control_state::kLanded; v.setZero(); p.z() = 0; cmd_ = {}; }
  void move(const MoveCommand& c) { cmd_ = c; hover_ = false; }
  void hover() { hover_ = true; }

  Eigen::Isometry3d pose() const { return make_pose(p, yaw, pitch, roll); }

  void step(double dt) {
    phase_t_ += dt;
    MoveCommand c = cmd_;
    if (control_state == control_state::kTakingOff) {  // take-off: climb to 0.7 m then hover
      v.z() = p.z() < 0.7 ? 0.6 : 0.0;
      if (p.z() >= 0.7 && phase_t_ > 1.5) control_state = control_state::kHovering;
      c = brake();
    } else if (control_state == control_state::kLanding) {
      v.z() = -0.5;
      c = brake();
      if (p.z() <= 0.01) { control_state = control_state::kLanded; v.setZero(); p.z() = 0; }
    } else if (control_state == control_state::kLanded) {
      v.setZero();
      return;
    } else if (hover_) {
      c = brake();
    }
    const double a = 1 - std::exp(-dt / 0.1);
    roll += a * (std::clamp(c.roll, -1.0, 1.0) * kMaxTilt - roll);
    pitch += a * (std::clamp(c.pitch, -1.0, 1.0) * kMaxTilt - pitch);
    const double af = kG * std::tan(pitch), al = -kG * std::tan(roll);
    const Eigen::Vector2d acc(std::cos(yaw) * af - std::sin(yaw) * al, std::sin(yaw) * af + std::cos(yaw) * al);
    v.head<2>() += (acc - kDrag * v.head<2>()) * dt;
    if (control_state::follows_commands(control_state)) {
      const double b = 1 - std::exp(-dt / 0.3);
      v.z() += b * (std::clamp(c.gaz, -1.0, 1.0) * kMaxVz - v.z());
      const double y = 1 - std::exp(-dt / 0.2);
      yaw_rate += y * (std::clamp(c.yaw_rate, -1.0, 1.0) * kMaxYawRate - yaw_rate);
      control_state = hover_ ? control_state::kHovering : control_state::kFlying;
    } else {
      yaw_rate = 0;
    }
    p += v * dt;
    yaw = wrap_angle(yaw + yaw_rate * dt);
    if (p.z() < 0) {
      if (v.z() < -0.8) crashed = true;
      p.z() = 0;
      v.z() = 0;
    }
    battery -= dt * 0.01;
  }

  NavdataSample navdata(double t) const {
    NavdataSample s;
    s.t = t;
    s.control_state = control_state;
    s.battery_percent = battery;
    s.roll_rad = roll;
    s.pitch_rad = pitch;
    s.yaw_rad = yaw;
    s.altitude_m = p.z();
    const double c = std::cos(yaw), sn = std::sin(yaw);
    s.vx_mps = c * v.x() + sn * v.y();
    s.vy_mps = -sn * v.x() + c * v.y();
    s.vz_mps = v.z();
    return s;
  }

 private:
  MoveCommand brake() const {
    const double c = std::cos(yaw), sn = std::sin(yaw);
    const double vf = c * v.x() + sn * v.y(), vl = -sn * v.x() + c * v.y();
    MoveCommand m;
    m.pitch = std::clamp(-0.6 * vf, -1.0, 1.0);
    m.roll = std::clamp(0.6 * vl, -1.0, 1.0);
    return m;
  }
  MoveCommand cmd_;
  bool hover_ = true;
  double phase_t_ = 0;
};

}  // namespace labo::bench
