#include "bench/sim/bench_sim_command.hpp"

#include <sched.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <opencv2/core.hpp>

#include "core/source_tree.hpp"
#include "core/cpu_time.hpp"
#include "drone/sim/ground_truth_log.hpp"
#include "drone/sim/sim_drone_link.hpp"
#include "drone/sim/sim_setup.hpp"
#include "localization/face/teacher_head.hpp"

namespace labo::bench {

using lab::LabDescription;

using sim::GroundTruthLog;
using sim::SimConfig;
using sim::SimDroneLink;
using sim::SimInputs;
using sim::SimLinkProfile;
using sim::SimLinkSettings;
using sim::SimProfile;
using sim::TexturedHeadModel;
using sim::load_sim_inputs;
using sim::make_simulated_lab;


namespace {

// Counts what the link delivers and touches every frame's pixels, as a consumer would.
struct CountingListener final : DroneLinkListener {
  long navdata = 0, frames = 0;
  double checksum = 0;
  void on_navdata(const NavdataSample& s) override {
    ++navdata;
    checksum += s.altitude_m;
  }
  void on_video(const VideoFrame& f) override {
    ++frames;
    checksum += f.bgr.at<cv::Vec3b>(f.bgr.rows / 2, f.bgr.cols / 2)[0];
  }
  void on_link_state(LinkState, Seconds) override {}
};

// An open-loop flight over the lab: take off, then a repeating pattern of moves and hovers that stays
// near the base (forward and back, left and right, turns, up and down), then land.
MoveCommand pattern(Seconds t) {
  const int phase = static_cast<int>(t / 2.0) % 10;
  switch (phase) {
    case 0: return {0.0, 0.3, 0.0, 0.0};
    case 2: return {0.0, -0.3, 0.0, 0.0};
    case 4: return {0.3, 0.0, 0.0, 0.4};
    case 6: return {-0.3, 0.0, 0.0, -0.4};
    case 8: return {0.0, 0.0, 0.4, 0.0};
    case 9: return {0.0, 0.0, -0.4, 0.0};
    default: return {};
  }
}

struct RunResult {
  double wall_s = 0, cpu_s = 0;
  SimProfile lab;
  SimLinkProfile link;
  long frames = 0, navdata = 0;
  int crashes = 0;
};

RunResult run_flight(const LabDescription& lab, const CamerasConfig& cameras, const SimConfig& config,
                     const TexturedHeadModel& head, Seconds duration, bool h264, GroundTruthLog* truth_log) {
  auto sim = make_simulated_lab(lab, cameras, config.lab, head);
  sim->set_profiling(true);
  SimLinkSettings ls = config.link;
  ls.h264 = h264;
  ls.both_cameras = true;
  ls.video_fps = 30;
  SimDroneLink link(*sim, ls);
  CountingListener listener;
  link.set_listener(&listener);
  const Seconds control_period = 0.03, airborne_at = 6.0, land_at = duration - 6.0;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  for (Seconds t = 0; t < duration; t += control_period) {
    link.advance_to(t);
    if (truth_log) truth_log->record(sim->truth(), sim->scene());
    if (t < 0.5) continue;
    if (t < airborne_at) {
      link.takeoff();
    } else if (t < land_at) {
      const MoveCommand m = pattern(t - airborne_at);
      if (m.roll == 0 && m.pitch == 0 && m.gaz == 0 && m.yaw_rate == 0) {
        link.hover();
      } else {
        link.move(m);
      }
    } else {
      link.land();
    }
  }
  RunResult r;
  r.cpu_s = process_cpu_seconds() - cpu_start;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.lab = sim->profile();
  r.link = link.profile();
  r.frames = listener.frames;
  r.navdata = listener.navdata;
  r.crashes = sim->truth().crashes;
  return r;
}

void print(const char* name, const RunResult& r, Seconds duration, double target) {
  const double speed = duration / r.cpu_s;
  const double renders = static_cast<double>(std::max(1L, r.lab.renders));
  const double encoded = static_cast<double>(std::max(1L, r.link.encoded));
  const double other_s = r.cpu_s - r.lab.physics_s - r.lab.sensors_s - r.lab.render_s - r.link.codec_s;
  std::printf("%-14s %5.1fx real time in CPU time (target >= %.0fx: %s), %5.1fx in wall time;  physics %5.2f ms/s  "
              "sensors %5.2f ms/s  render %5.2f ms/frame  H.264 %5.2f ms/frame  other %5.2f ms/s  [%ld frames, %ld "
              "navdata, %d crashes]\n",
              name, speed, target, speed >= target ? "met" : "MISSED", duration / r.wall_s, 1e3 * r.lab.physics_s / duration,
              1e3 * r.lab.sensors_s / duration, 1e3 * r.lab.render_s / renders,
              r.link.encoded ? 1e3 * r.link.codec_s / encoded : 0.0, 1e3 * other_s / duration, r.frames, r.navdata,
              r.crashes);
}

// The 1-minute load average: when it exceeds the cores, wall time measures the neighbours too.
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string first;
  in >> first;
  return first.empty() ? "unknown" : first;
}

}  // namespace

const CommandSpec& bench_sim_command_spec() {
  static const CommandSpec spec{
      "bench sim",
      "",
      "Lockstep flight with both cameras rendered at 30 fps, on one core: speed as a multiple of real time "
      "without and with H.264, and the time per stage.",
      {{"--config", "FILE", "configuration file: cameras, lab, sim (default: config/default.json)"},
       {"--seconds", "S", "simulated flight time per run (default 40)"},
       {"--ground-truth", "FILE", "write the first run's ground truth (CSV, and FILE's stem + _objects.csv)"}},
      0,
      0};
  return spec;
}

int run_bench_sim_command(const ParsedArgs& args) {
  const std::filesystem::path config_file =
      args.value_or("--config", (source_root() / "config" / "default.json").string());
  const double duration = args.number_or("--seconds", 40.0, 15.0, 3600.0);
  const SimInputs in = load_sim_inputs(config_file);
  const CamerasConfig& cameras = in.cameras;
  const SimConfig& sim = in.sim;
  const LabDescription& lab = in.lab;
  const TexturedHeadModel head = face::load_lab_teacher_head(lab);

  // One core: pin the process to the CPU it runs on, and no OpenCV worker threads.
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(sched_getcpu(), &one);
  const bool pinned = sched_setaffinity(0, sizeof one, &one) == 0;
  cv::setNumThreads(1);
  std::printf("bench sim: %.0f s lockstep flight, both cameras %dx%d and %dx%d rendered at 30 fps, navdata %s, physics "
              "step %.1f ms, %s\n",
              duration, cameras.front.width, cameras.front.height, cameras.bottom.width, cameras.bottom.height,
              sim.link.full_navdata ? "200 Hz" : "15 Hz", 1e3 * sim.lab.dynamics.step_s,
              pinned ? "pinned to one core" : "NOT pinned (sched_setaffinity failed)");
  std::printf("speed = simulated time / process CPU time (the target's measure on a shared machine); load average %s\n",
              load_average().c_str());
  std::optional<GroundTruthLog> truth_log;
  if (const auto file = args.value("--ground-truth")) truth_log.emplace(*file, lab);
  print("without H.264", run_flight(lab, cameras, sim, head, duration, false, truth_log ? &*truth_log : nullptr), duration, 5.0);
  print("with H.264", run_flight(lab, cameras, sim, head, duration, true, nullptr), duration, 2.0);
  if (truth_log) std::printf("ground truth: %zu rows in %s\n", truth_log->rows(), args.value("--ground-truth")->c_str());
  return 0;
}

}  // namespace labo::bench
