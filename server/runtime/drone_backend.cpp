#include "server/runtime/drone_backend.hpp"

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "control/flight_stack.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/replay/replay_link.hpp"
#include "drone/sim/sim_setup.hpp"
#include "localization/face/teacher_head.hpp"
#include "server/runtime/flight_runtime.hpp"
#include "server/runtime/flight_stack_core.hpp"

namespace labo {

namespace {

control::FlightStackSetup flight_setup(const AppConfig& config) {
  // The lab's geometry (room, base, instruments, platform) from the lab description the config
  // names (validated when the config was loaded).
  control::FlightStackSetup setup;
  setup.lab = fusion::lab_geometry_from(config.lab);
  setup.control = config.control;
  setup.cameras = config.cameras;
  setup.vision = config.vision;
  setup.estimation = config.estimation;
  // The real vision pipelines on the drone's frames (localization/fusion/lab_pipelines_factory.hpp).
  setup.front_ends = fusion::FrontEndSettings{config.planar, config.slam, config.face, true};
  return setup;
}

FlightRuntimeOptions runtime_options(const AppConfig& config) {
  FlightRuntimeOptions o;
  o.jpeg_quality = config.server.video.jpeg_quality;
  o.front_camera = PinholeCamera(config.cameras.front);
  return o;
}

// A real AR.Drone 2.0 over Wi-Fi.
class ArdroneBackend final : public DroneBackend {
 public:
  ArdroneBackend(const DroneSpec& spec, const AppConfig& config, Logger log)
      : link_([&] {
          ArdroneLinkSettings s = config.link;
          s.host = spec.host;
          return s;
        }(), log.child("link")),
        core_(std::make_unique<control::FlightStack>(flight_setup(config)), config.cameras),
        runtime_(link_, core_, clock_, runtime_options(config), log) {
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

// Replay time: the recording's first timestamp plus the wall time since the start.
class ReplayClock final : public Clock {
 public:
  explicit ReplayClock(Seconds first) : first_(first) {}
  Seconds now() const override { return first_ + wall_.now(); }

 private:
  Seconds first_;
  SteadyClock wall_;
};

// A recorded flight, played back in real time; commands are ignored by the replay link.
class ReplayBackend final : public DroneBackend {
 public:
  ReplayBackend(const DroneSpec& spec, const AppConfig& config, Logger log)
      : link_(spec.file, log.child("replay")),
        clock_(std::isfinite(link_.next_time()) ? link_.next_time() : 0.0),
        core_(std::make_unique<control::FlightStack>(flight_setup(config)), config.cameras),
        runtime_(link_, core_, clock_, runtime_options(config), log) {
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
      : lab_(make_lab(config)),
        emulator_(*lab_, emulator_settings(config), log.child("emulator")),
        link_(link_settings(config, emulator_), log.child("link")),
        core_(std::make_unique<control::FlightStack>(flight_setup(config)), config.cameras),
        runtime_(link_, core_, clock_, runtime_options(config), log) {
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
  // The lab's cameras show the teacher's face textured from their photograph, built here because
  // drone/ cannot call localization/. The world is the config's `sim.world` (the flight runtime is
  // built from the config alone; a randomized world's delays are the loopback's, not drawn ones).
  static std::unique_ptr<SimulatedLab> make_lab(const AppConfig& config) {
    return make_simulated_lab(make_sim_world(config.lab, config.cameras, config.sim),
                              face::load_lab_teacher_head(config.lab, config.face));
  }
  static ArdroneEmulatorSettings emulator_settings(const AppConfig& config) {
    ArdroneEmulatorSettings s = config.emulator;
    s.bind_host = "127.0.0.1";
    s.at_port = s.navdata_port = s.video_port = 0;
    return s;
  }
  // Starts the emulator (its ports are known once bound) and points the driver at it.
  static ArdroneLinkSettings link_settings(const AppConfig& config, ArdroneEmulator& emulator) {
    emulator.start();
    ArdroneLinkSettings s = config.link;
    s.host = "127.0.0.1";
    s.at_port = emulator.at_port();
    s.navdata_port = emulator.navdata_port();
    s.video_port = emulator.video_port();
    return s;
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
    case DroneSpec::Kind::Replay: return std::make_unique<ReplayBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Sim: return std::make_unique<SimBackend>(config, std::move(log));
  }
  throw std::logic_error("unknown drone kind");
}

}  // namespace labo
