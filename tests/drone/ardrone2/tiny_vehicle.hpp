#pragma once
// A tiny EmulatedVehicle for the loopback tests: first-order kinematics, a take-off/landing sequence,
// and a flat-coloured view per camera (front red, bottom green). Thread-safe snapshot for the test.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <opencv2/core.hpp>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/emulated_vehicle.hpp"

namespace labo::test {

class TinyVehicle : public EmulatedVehicle {
 public:
  struct Snapshot {
    double x_m = 0, y_m = 0, z_m = 0, yaw_rad = 0;
    bool flying = false, hovering = false;
    int flat_trims = 0;
    MoveCommand last_move;
  };

  void takeoff(Seconds) override { std::lock_guard l(m_); if (!emergency_) { taking_off_ = true; landing_ = false; } }
  void land(Seconds) override {
    std::lock_guard l(m_);
    if (!s_.flying) return;  // as a firmware: "land" on the ground does nothing
    landing_ = true;
    taking_off_ = false;
  }
  // Puts the vehicle in the air at `altitude_m`, as if it had taken off under an emulator now gone.
  void start_flying(double altitude_m) { std::lock_guard l(m_); s_.flying = true; s_.z_m = altitude_m; }
  void emergency(Seconds) override { std::lock_guard l(m_); emergency_ = !emergency_; s_.flying = false; s_.z_m = 0; }
  void flat_trim(Seconds) override { std::lock_guard l(m_); ++s_.flat_trims; }
  void move(const MoveCommand& c, bool hover, Seconds) override {
    std::lock_guard l(m_);
    s_.hovering = hover;
    if (!hover) s_.last_move = c;
  }
  void select_camera(CameraId camera, Seconds) override { std::lock_guard l(m_); camera_ = camera; }

  void advance_to(Seconds t) override {
    std::lock_guard l(m_);
    const double dt = t > t_ ? t - t_ : 0.0;
    t_ = std::max(t, t_);
    const MoveCommand c = s_.hovering ? MoveCommand{} : s_.last_move;
    if (taking_off_) {
      s_.flying = true;
      s_.z_m = std::min(0.8, s_.z_m + 1.0 * dt);
      if (s_.z_m >= 0.8) taking_off_ = false;
    } else if (landing_) {
      s_.z_m = std::max(0.0, s_.z_m - 1.0 * dt);
      if (s_.z_m <= 0.0) { landing_ = false; s_.flying = false; }
    }
    const bool airborne = s_.flying && !taking_off_ && !landing_;
    vx_ = airborne ? 2.0 * c.pitch : 0.0;   // pitch > 0 = forward
    vy_ = airborne ? -2.0 * c.roll : 0.0;   // roll > 0 = right = -y
    yaw_rate_ = airborne ? 1.0 * c.yaw_rate : 0.0;
    s_.yaw_rad += yaw_rate_ * dt;
    s_.x_m += (std::cos(s_.yaw_rad) * vx_ - std::sin(s_.yaw_rad) * vy_) * dt;
    s_.y_m += (std::sin(s_.yaw_rad) * vx_ + std::cos(s_.yaw_rad) * vy_) * dt;
    pitch_ = airborne ? 0.2 * c.pitch : 0.0;
    roll_ = airborne ? 0.2 * c.roll : 0.0;
  }
  Seconds now() const override { std::lock_guard l(m_); return t_; }
  VehicleTelemetry telemetry() const override {
    std::lock_guard l(m_);
    VehicleTelemetry tel;
    tel.nav.t = t_;
    tel.nav.control_state = !s_.flying ? 2 : taking_off_ ? 6 : landing_ ? 8 : s_.hovering ? 4 : 3;
    tel.nav.battery_percent = 80;
    tel.nav.roll_rad = roll_;
    tel.nav.pitch_rad = pitch_;
    tel.nav.yaw_rad = s_.yaw_rad;
    tel.nav.altitude_m = s_.z_m;
    tel.nav.vx_mps = vx_;
    tel.nav.vy_mps = vy_;
    tel.flying = s_.flying;
    tel.emergency = emergency_;
    return tel;
  }
  CameraId selected_camera() const override { std::lock_guard l(m_); return camera_; }
  void render(CameraId camera, cv::Mat& bgr) override {
    bgr.create(360, 640, CV_8UC3);
    bgr.setTo(camera == CameraId::Front ? cv::Scalar(40, 40, 220) : cv::Scalar(40, 220, 40));
    std::lock_guard l(m_);
    // A moving square so that P frames carry something.
    const int x = static_cast<int>(t_ * 60.0) % 560;
    bgr(cv::Rect(x, 150, 60, 60)).setTo(cv::Scalar(255, 255, 255));
  }
  Snapshot snapshot() const { std::lock_guard l(m_); return s_; }

 private:
  mutable std::mutex m_;
  Snapshot s_;
  Seconds t_ = 0;
  bool taking_off_ = false, landing_ = false, emergency_ = false;
  double vx_ = 0, vy_ = 0, yaw_rate_ = 0, pitch_ = 0, roll_ = 0;
  CameraId camera_ = CameraId::Front;
};

// Driver settings that talk to `emulator` on loopback (its ports are chosen by the OS).
inline ardrone2::ArdroneLinkSettings link_settings_for(const ardrone2::ArdroneEmulator& emulator) {
  ardrone2::ArdroneLinkSettings ls;
  ls.host = "127.0.0.1";
  ls.at_port = emulator.at_port();
  ls.navdata_port = emulator.navdata_port();
  ls.video_port = emulator.video_port();
  return ls;
}

}  // namespace labo::test
