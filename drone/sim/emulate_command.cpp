#include "drone/sim/emulate_command.hpp"

#include <csignal>
#include <ctime>
#include <iomanip>
#include <iostream>

#include "core/config_reader.hpp"
#include "core/log.hpp"
#include "core/source_tree.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/sim/sim_setup.hpp"
#include "drone/tello/tello_config.hpp"

namespace labo::sim {

using ardrone2::ArdroneEmulator;
using ardrone2::ArdroneEmulatorSettings;
using lab::LabDescription;
using tello::TelloConfig;
using tello::TelloEmulator;
using tello::TelloEmulatorSettings;
using tello::read_tello_config_of;
using tello::tello_cameras;


namespace {

// Blocks SIGINT and SIGTERM in this thread and in the threads it starts afterwards, so that they
// are taken by wait_for_signal() instead of killing the process mid-packet.
sigset_t block_stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

// True when a stop signal arrived within `timeout_s`.
bool wait_for_signal(const sigset_t& set, double timeout_s) {
  timespec ts;
  ts.tv_sec = static_cast<time_t>(timeout_s);
  ts.tv_nsec = static_cast<long>((timeout_s - static_cast<double>(ts.tv_sec)) * 1e9);
  return sigtimedwait(&set, nullptr, &ts) > 0;
}

}  // namespace

const CommandSpec& emulate_command_spec() {
  static const CommandSpec spec{
      "emulate",
      "",
      "Run the simulated lab as an AR.Drone 2.0 (UDP 5556/5554, TCP 5555) or a Tello (UDP 8889, state to 8890, "
      "H.264 to 11111) until Ctrl-C.",
      {{"--config", "FILE", "configuration file: cameras, emulator ports, lab, sim (default: config/default.json)"},
       {"--protocol", "ardrone|tello", "the drone it answers as (default: ardrone)"},
       {"--bind", "ADDR", "address to listen on (default: the config's emulator.bind_host or tello.emulator.bind_host)"},
       {"--lab", "FILE", "lab description (default: the config's lab)"},
       {"--seconds", "S", "stop after S seconds (default: run until Ctrl-C)"}},
      0,
      0};
  return spec;
}

namespace {

// The emulator of the chosen protocol over the vehicle, started; it stops when destroyed.
struct RunningEmulator {
  std::unique_ptr<ArdroneEmulator> ardrone;
  std::unique_ptr<TelloEmulator> tello;
};

RunningEmulator start_emulator(const std::string& protocol, EmulatedVehicle& vehicle, const SimInputs& in,
                               const TelloConfig& tello, const std::optional<std::string>& bind, Logger log) {
  RunningEmulator e;
  if (protocol == "tello") {
    TelloEmulatorSettings settings = tello.emulator;
    settings.bind_host = bind.value_or(settings.bind_host);
    e.tello = std::make_unique<TelloEmulator>(vehicle, settings, std::move(log));
    e.tello->start();  // throws naming the port when it is taken
    std::cout << "Tello (SDK 2.0) emulator on " << settings.bind_host << ": commands UDP " << e.tello->command_port()
              << ", state to UDP " << settings.client_state_port << " and H.264 to UDP " << settings.client_video_port
              << " of the host that sends \"command\"";
  } else {
    ArdroneEmulatorSettings settings = in.emulator;
    settings.bind_host = bind.value_or(settings.bind_host);
    e.ardrone = std::make_unique<ArdroneEmulator>(vehicle, settings, std::move(log));
    e.ardrone->start();
    std::cout << "AR.Drone 2.0 emulator on " << settings.bind_host << ": AT UDP " << e.ardrone->at_port()
              << ", navdata UDP " << e.ardrone->navdata_port() << ", video TCP " << e.ardrone->video_port();
  }
  return e;
}

}  // namespace

int run_emulate_command(const ParsedArgs& args, const TeacherHeadLoader& load_head) {
  const std::filesystem::path config_file =
      args.value_or("--config", (source_root() / "config" / "default.json").string());
  const double seconds = args.number_or("--seconds", 0.0, 0.0, 1e9);
  const std::string protocol = args.value_or("--protocol", "ardrone");
  if (protocol != "ardrone" && protocol != "tello")
    throw UsageError("--protocol: '" + protocol + "' is not ardrone or tello");
  const std::optional<std::string> lab_file = args.value("--lab");
  SimInputs in = load_sim_inputs(config_file, lab_file ? std::optional<std::filesystem::path>(*lab_file) : std::nullopt);
  const LabDescription& lab = in.lab;
  // A Tello's lab renders the Tello's camera (960x720, its field of view) in front.
  const TelloConfig tello = read_tello_config_of(ConfigDocument::load(config_file).root());
  const CamerasConfig cameras = protocol == "tello" ? tello_cameras(tello, in.cameras) : in.cameras;

  const sigset_t stop_signals = block_stop_signals();
  Logger log("labodrone", LogLevel::Info);
  auto vehicle = make_simulated_lab(make_sim_world(lab, cameras, in.sim), load_head(lab));
  RunningEmulator emulator = start_emulator(protocol, *vehicle, in, tello, args.value("--bind"), log.child("emulator"));
  std::cout << " (lab " << lab.source.string() << "); Ctrl-C stops" << std::endl;
  SteadyClock clock;
  while (!(seconds > 0 && clock.now() >= seconds)) {
    const double wait = seconds > 0 ? std::min(10.0, seconds - clock.now()) : 10.0;
    if (wait_for_signal(stop_signals, std::max(0.01, wait))) break;
  }
  emulator = {};
  const QuadrotorState& s = vehicle->truth();
  std::cout << std::fixed << std::setprecision(2) << "stopped at t=" << s.t << " s: " << to_string(s.phase)
            << " at (" << s.position_m.x() << ", " << s.position_m.y() << ", " << s.position_m.z() << ") m, battery "
            << s.battery_percent << "%, crashes " << s.crashes << std::endl;
  return 0;
}

}  // namespace labo::sim
