#include "server/runtime/drone_backend.hpp"

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "control/flight_stack.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/replay/replay_link.hpp"
#include "drone/tello/tello_link.hpp"
#include "server/runtime/backend_parts.hpp"
#include "server/runtime/flight_runtime.hpp"
#include "server/runtime/flight_stack_core.hpp"

namespace labo::server {

using ardrone2::ArdroneEmulator;
using ardrone2::ArdroneLink;
using ardrone2::ArdroneLinkSettings;
using lab::InstrumentSpec;
using replay::RecordedDrone;
using replay::ReplayLink;
using replay::recorded_drone;
using tello::TelloLink;
using tello::TelloLinkSettings;
using tello::tello_cameras;

using sim::SimulatedLab;


namespace {

// A real AR.Drone 2.0 over Wi-Fi.
class ArdroneBackend final : public DroneBackend {
 public:
  ArdroneBackend(const DroneSpec& spec, const AppConfig& config, Logger log)
      : link_([&] {
          ArdroneLinkSettings s = config.link;
          s.host = spec.host;
          return s;
        }(), log.child("link")),
        core_(std::make_unique<control::FlightStack>(flight_stack_setup(config)), config.cameras),
        runtime_(link_, core_, clock_, flight_runtime_options(config, link_), log) {
    runtime_.start();
    link_.start();
  }
  ~ArdroneBackend() override {
    runtime_.land_and_stop(0);
    link_.stop();
  }
  FlightService& flight() override { return runtime_; }

 private:
  // ArdroneLink stamps with its own SteadyClock, created a few microseconds after this one.
  SteadyClock clock_;
  ArdroneLink link_;
  FlightStackCore core_;
  FlightRuntime runtime_;
};

// A Tello (or Tello EDU) in SDK 2.0 mode over Wi-Fi, with its own camera in front. The bottom camera
// is the Tello EDU's downward camera ("downvision", with tello.link.downvision); a plain Tello refuses
// it, and without it the platform search lands at the estimated base when it times out (docs/tello.md
// "Landing without a bottom camera"); said once at start.
FlightRuntimeOptions tello_runtime_options(const AppConfig& config) {
  FlightRuntimeOptions o = flight_runtime_options(
      config, "Tello", "tello.link.downvision is off: the Tello streams its front camera only, there is no bottom camera");
  if (config.tello.link.downvision) {
    o.video.bottom_camera = true;  // a Tello that refuses "downvision 1" falls back in the link, counted and logged
    o.video.no_bottom_camera.clear();
  }
  return o;
}

class TelloBackend final : public DroneBackend {
 public:
  TelloBackend(const DroneSpec& spec, const AppConfig& config, Logger log)
      : cameras_(tello_cameras(config.tello, config.cameras)),
        link_([&] {
          TelloLinkSettings s = config.tello.link;
          s.host = spec.host;
          return s;
        }(), log.child("link")),
        core_(std::make_unique<control::FlightStack>(flight_stack_setup(config, cameras_, config.tello_estimation)), cameras_),
        runtime_(link_, core_, clock_, tello_runtime_options(config), log) {
    if (config.tello.link.downvision)
      log.info(clock_.now(), "bottom camera: the Tello EDU's downward camera (downvision); a Tello that refuses it "
                             "streams its front camera and the platform stage lands at the estimated base")
          .kv("after_s", config.control.mission.detect_timeout_s);
    else
      log.warn(clock_.now(), "tello.link.downvision is off: no bottom camera, the platform stage lands at the estimated base")
          .kv("after_s", config.control.mission.detect_timeout_s);
    runtime_.start();
    link_.start();
  }
  ~TelloBackend() override {
    runtime_.land_and_stop(0);
    link_.stop();
  }
  FlightService& flight() override { return runtime_; }

 private:
  CamerasConfig cameras_;
  SteadyClock clock_;
  TelloLink link_;
  FlightStackCore core_;
  FlightRuntime runtime_;
};

// Replay time: the recording's first timestamp plus the wall time since the start.
class ReplayClock final : public Clock {
 public:
  explicit ReplayClock(Seconds first) : first_(first) {}
  Seconds now() const override { return first_ + wall_.now(); }

 private:
  Seconds first_;
  SteadyClock wall_;
};

// A recorded flight, played back in real time; commands are ignored by the replay link. A Tello's
// recording is seen through the Tello's camera.
class ReplayBackend final : public DroneBackend {
 public:
  ReplayBackend(const DroneSpec& spec, const AppConfig& config, Logger log)
      : cameras_(recorded_drone(spec.file) == RecordedDrone::Tello ? tello_cameras(config.tello, config.cameras)
                                                                   : config.cameras),
        link_(spec.file, log.child("replay")),
        clock_(std::isfinite(link_.next_time()) ? link_.next_time() : 0.0),
        core_(std::make_unique<control::FlightStack>(flight_stack_setup(
                  config, cameras_,
                  recorded_drone(spec.file) == RecordedDrone::Tello ? config.tello_estimation : config.estimation)),
              cameras_),
        runtime_(link_, core_, clock_,
                 flight_runtime_options(config, "recording", "a recording plays the camera it recorded: nothing reaches a drone"),
                 log) {
    runtime_.start();
    player_ = std::thread([this] {
      while (running_ && link_.advance_to(clock_.now())) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    });
  }
  ~ReplayBackend() override {
    running_ = false;
    if (player_.joinable()) player_.join();
    runtime_.land_and_stop(0);
  }
  FlightService& flight() override { return runtime_; }

 private:
  CamerasConfig cameras_;
  ReplayLink link_;
  ReplayClock clock_;
  FlightStackCore core_;
  FlightRuntime runtime_;
  std::atomic<bool> running_{true};
  std::thread player_;
};

// The simulated lab as an AR.Drone 2.0 on loopback, flown by the real driver: SimulatedLab under
// ArdroneEmulator (real time, free ports so several servers and tests can run side by side),
// ArdroneLink connected to it, and the flight runtime on top exactly as for a real drone.
class SimBackend final : public DroneBackend {
 public:
  SimBackend(const AppConfig& config, Logger log)
      : lab_(make_configured_lab(config)),
        emulator_(*lab_, loopback_emulator_settings(config), log.child("emulator")),
        link_(link_settings(config, emulator_), log.child("link")),
        core_(std::make_unique<control::FlightStack>(flight_stack_setup(config)), config.cameras),
        runtime_(link_, core_, clock_, sim_runtime_options(config), log) {
    // The page shows the lab's truth beside the estimate (dashed grey), as the experiments' plots do.
    core_.set_truth_source([this]() -> std::optional<Eigen::Isometry3d> {
      Eigen::Isometry3d T_world_body;
      emulator_.with_vehicle([&](const EmulatedVehicle&) { T_world_body = lab_->truth().T_world_body(); });
      return T_world_body;
    });
    runtime_.start();
    link_.start();
  }
  ~SimBackend() override {
    runtime_.land_and_stop(0);  // the web server has landed the drone already
    link_.stop();
    emulator_.stop();
  }
  FlightService& flight() override { return runtime_; }

 private:
  // An instrument the flight software has placed is drawn in the simulated lab where it said.
  FlightRuntimeOptions sim_runtime_options(const AppConfig& config) {
    FlightRuntimeOptions o = flight_runtime_options(config, link_);
    o.place_in_world = [this](const InstrumentSpec& instrument) {
      emulator_.change_vehicle([&](EmulatedVehicle&) { lab_->add_instrument(instrument); });
    };
    return o;
  }
  // Starts the emulator (its ports are known once bound) and points the driver at it.
  static ArdroneLinkSettings link_settings(const AppConfig& config, ArdroneEmulator& emulator) {
    emulator.start();
    return loopback_link_settings(config, emulator.at_port(), emulator.navdata_port(), emulator.video_port());
  }

  std::unique_ptr<SimulatedLab> lab_;
  ArdroneEmulator emulator_;
  SteadyClock clock_;
  ArdroneLink link_;
  FlightStackCore core_;
  FlightRuntime runtime_;
};

}  // namespace

std::unique_ptr<DroneBackend> make_drone_backend(const DroneSpec& spec, const AppConfig& config, Logger log) {
  switch (spec.kind) {
    case DroneSpec::Kind::Ardrone: return std::make_unique<ArdroneBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Tello: return std::make_unique<TelloBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Replay: return std::make_unique<ReplayBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Sim: return std::make_unique<SimBackend>(config, std::move(log));
  }
  throw std::logic_error("unknown drone kind");
}

}  // namespace labo::server
