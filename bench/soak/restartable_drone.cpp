#include "bench/soak/restartable_drone.hpp"

#include <stdexcept>

#include "server/runtime/backend_parts.hpp"

namespace labo::bench {

using ardrone2::ArdroneEmulator;
using ardrone2::ArdroneEmulatorSettings;

using sim::QuadrotorState;
using sim::SimulatedLab;
using sim::to_string;

using server::AppConfig;
using server::loopback_emulator_settings;
using server::make_configured_lab;


RestartableDrone::RestartableDrone(const AppConfig& config, Logger log)
    : config_(config), log_(std::move(log)), lab_(make_configured_lab(config)) {
  std::lock_guard lock(mutex_);
  emulator_ = std::make_unique<ArdroneEmulator>(*lab_, loopback_emulator_settings(config_), log_.child("emulator"));
  emulator_->start();
  at_port_ = emulator_->at_port();
  navdata_port_ = emulator_->navdata_port();
  video_port_ = emulator_->video_port();
  ++starts_;
}

RestartableDrone::~RestartableDrone() { stop(); }

void RestartableDrone::stop() {
  // Under the lock: with_lab() must not read the lab directly while the emulator's threads still run
  // (they never take this lock, so joining them here cannot deadlock).
  std::lock_guard lock(mutex_);
  if (emulator_) emulator_->stop();
  emulator_.reset();
}

void RestartableDrone::start() {
  std::lock_guard lock(mutex_);
  if (emulator_) return;
  ArdroneEmulatorSettings s = loopback_emulator_settings(config_);
  s.at_port = at_port_;
  s.navdata_port = navdata_port_;
  s.video_port = video_port_;
  auto emulator = std::make_unique<ArdroneEmulator>(*lab_, s, log_.child("emulator"));
  emulator->start();  // throws when a port was taken meanwhile
  emulator_ = std::move(emulator);
  ++starts_;
}

void RestartableDrone::replace_lab(const AppConfig& config, const Eigen::Vector2d& xy, double yaw_rad) {
  std::lock_guard lock(mutex_);
  if (emulator_) throw std::logic_error("RestartableDrone::replace_lab: stop the emulator first");
  // lab.T_world_base is where a simulated lab starts its drone; only the simulation reads it (the
  // flight software keeps the lab's own base), so it sees nothing but a new battery.
  AppConfig c = config;
  const Eigen::Vector3d at(xy.x(), xy.y(), lab_->dynamics().collision().support_height({xy.x(), xy.y(), 10.0}));
  c.lab.T_world_base = Eigen::Isometry3d(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()));
  c.lab.T_world_base.translation() = at;
  lab_ = make_configured_lab(c);
}

template <typename F>
void RestartableDrone::with_lab(F&& f) const {
  std::lock_guard lock(mutex_);
  if (emulator_) {
    emulator_->with_vehicle([&](const EmulatedVehicle&) { f(static_cast<const SimulatedLab&>(*lab_)); });
  } else {
    f(static_cast<const SimulatedLab&>(*lab_));
  }
}

DroneTruth RestartableDrone::truth() const {
  DroneTruth t;
  with_lab([&](const SimulatedLab& lab) {
    const QuadrotorState& s = lab.truth();
    t.airborne = s.airborne();
    t.phase = to_string(s.phase);
    t.battery_percent = s.battery_percent;
    t.position_m = s.position_m;
    t.yaw_rad = s.yaw_rad;
    t.crashes = s.crashes;
    t.crash_reason = s.crash_reason;
  });
  std::lock_guard lock(mutex_);
  t.emulator_running = emulator_ != nullptr;
  return t;
}

Eigen::Isometry3d RestartableDrone::T_world_body() const {
  Eigen::Isometry3d T;
  with_lab([&](const SimulatedLab& lab) { T = lab.truth().T_world_body(); });
  return T;
}

int RestartableDrone::starts() const {
  std::lock_guard lock(mutex_);
  return starts_;
}

}  // namespace labo::bench
