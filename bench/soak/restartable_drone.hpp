#pragma once
// The simulated lab under the AR.Drone 2.0 emulator on loopback, the drone `labodrone serve --drone
// sim` flies, as a drone the soak can switch off and on: stop() ends the emulator (its sockets
// close; the simulated physics wait), start() starts a new emulator on the same ports over the same
// lab (its time continues the lab's), and replace_lab() swaps in a fresh lab while it is off: a
// battery swap, the new lab's drone standing where the old one stood (lab.T_world_base is where a
// simulated lab starts its drone), so the flight software sees nothing but the new battery.
#include <Eigen/Geometry>
#include <memory>
#include <mutex>

#include "core/log.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "server/app_config.hpp"

namespace labo::bench {

using sim::SimulatedLab;


using server::AppConfig;


// The lab's truth, for the soak's checks (the flight software never sees it).
struct DroneTruth {
  bool airborne = false;
  std::string phase;  // the firmware's: landed, taking_off, flying, hovering, landing, emergency
  double battery_percent = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // the hull's underside
  double yaw_rad = 0;
  int crashes = 0;
  std::string crash_reason;  // what the hull last hit
  bool emulator_running = false;
};

class RestartableDrone {
 public:
  // Builds the lab of `config` and starts the emulator on free loopback ports.
  RestartableDrone(const AppConfig& config, Logger log);
  ~RestartableDrone();

  int at_port() const { return at_port_; }
  int navdata_port() const { return navdata_port_; }
  int video_port() const { return video_port_; }

  void stop();
  void start();  // a new emulator on the same ports; no-op when running
  // While stopped: a new lab from `config` (its sim section: the battery, the seed), its drone
  // landed at (x, y) with `yaw_rad`, on whatever surface is there (floor, bench top, platform).
  void replace_lab(const AppConfig& config, const Eigen::Vector2d& xy, double yaw_rad);

  DroneTruth truth() const;
  Eigen::Isometry3d T_world_body() const;
  int starts() const;

 private:
  // Runs f(lab) under the running emulator's vehicle lock, or directly when it is stopped.
  template <typename F>
  void with_lab(F&& f) const;

  AppConfig config_;
  Logger log_;
  mutable std::mutex mutex_;  // guards lab_ and emulator_ against the soak's and the server's threads
  std::unique_ptr<SimulatedLab> lab_;
  std::unique_ptr<ardrone2::ArdroneEmulator> emulator_;
  int at_port_ = 0, navdata_port_ = 0, video_port_ = 0;
  int starts_ = 0;
};

}  // namespace labo::bench
