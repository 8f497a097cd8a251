#include "server/runtime/drone_backend.hpp"

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "control/flight_stack.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/replay/replay_link.hpp"
#include "server/runtime/flight_runtime.hpp"
#include "server/runtime/flight_stack_core.hpp"

namespace labo {

namespace {

FlightStackSetup flight_setup(const AppConfig& config) {
  // The lab's geometry (room, base, instruments, platform) from the lab description the config
  // names (validated when the config was loaded).
  FlightStackSetup setup;
  setup.lab = lab_geometry_from(config.lab);
  setup.control = config.control;
  setup.cameras = config.cameras;
  setup.vision = config.vision;
  setup.estimation = config.estimation;
  // The real vision pipelines on the drone's frames (control/lab_pipelines_factory.hpp).
  setup.front_ends = FrontEndSettings{config.planar, config.slam, config.face, true};
  return setup;
}

FlightRuntimeOptions runtime_options(const AppConfig& config) {
  FlightRuntimeOptions o;
  o.jpeg_quality = config.server.video.jpeg_quality;
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
        core_(std::make_unique<FlightStack>(flight_setup(config)), config.cameras),
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
        core_(std::make_unique<FlightStack>(flight_setup(config)), config.cameras),
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

}  // namespace

std::unique_ptr<DroneBackend> make_drone_backend(const DroneSpec& spec, const AppConfig& config, Logger log) {
  switch (spec.kind) {
    case DroneSpec::Kind::Ardrone: return std::make_unique<ArdroneBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Replay: return std::make_unique<ReplayBackend>(spec, config, std::move(log));
    case DroneSpec::Kind::Sim: break;
  }
  // The simulated lab (SimulatedLab under ArdroneEmulator) is branch sim's; not merged in this build.
  throw std::runtime_error("--drone sim needs the simulated lab (branch sim), not merged in this build yet; "
                           "use --drone ardrone[:HOST] or --drone replay:FILE");
}

}  // namespace labo
