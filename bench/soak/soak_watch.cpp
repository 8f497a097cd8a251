#include "bench/soak/soak_watch.hpp"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <malloc.h>

#include "bench/soak/soak_client.hpp"

namespace labo::bench {

using server::FlightService;
using server::FlightTelemetry;


double resident_mib() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  return 0;
}

RssSample with_heap_figures(RssSample sample) {
  const struct mallinfo2 m = mallinfo2();
  constexpr double kMiB = 1024.0 * 1024.0;
  sample.heap_in_use_mib = static_cast<double>(m.uordblks + m.hblkhd) / kMiB;
  sample.heap_held_mib = static_cast<double>(m.arena + m.hblkhd) / kMiB;
  return sample;
}

namespace {

TrailPose trail_pose(double x_m, double y_m, double z_m, double yaw_rad) {
  return {x_m, y_m, z_m, yaw_rad * 180.0 / 3.14159265358979323846};
}

}  // namespace

TrailPoint trail_point(double t_s, const DroneTruth& truth, const FlightTelemetry& telemetry) {
  TrailPoint p;
  p.t_s = t_s;
  p.truth = trail_pose(truth.position_m.x(), truth.position_m.y(), truth.position_m.z(), truth.yaw_rad);
  p.estimate = trail_pose(telemetry.pose.x_m, telemetry.pose.y_m, telemetry.pose.z_m, telemetry.pose.yaw_rad);
  if (const auto& d = telemetry.desired) p.desired = trail_pose(d->x_m, d->y_m, d->z_m, d->yaw_rad);
  p.source = server::to_string(telemetry.source);
  p.slam = telemetry.slam_state;
  p.stage = telemetry.stage;
  p.link = telemetry.link_state;
  return p;
}

std::string drone_activity(const DroneTruth& truth, const FlightTelemetry& telemetry) {
  if (!truth.airborne) return "landed";
  if (telemetry.mission != "idle" && !telemetry.mission.empty()) return "mission " + telemetry.mission;
  return "flying without a mission";
}

SoakWatch::SoakWatch(RestartableDrone& drone, FlightService& flight, unsigned short port, double probe_every_s)
    : drone_(drone), flight_(flight), port_(port), probe_every_s_(probe_every_s), thread_([this] { run(); }) {}

SoakWatch::~SoakWatch() { stop(); }

void SoakWatch::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

double SoakWatch::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void SoakWatch::run() {
  double next_probe = 0;
  while (running_) {
    const double t = elapsed_s();
    sample_flight(t);
    if (t >= next_probe) {
      next_probe = t + probe_every_s_;
      ++probes_;
      if (http_request(port_, "GET", "/api/health").status != 200) ++probe_failures_;
      std::lock_guard lock(mutex_);
      RssSample sample = with_heap_figures({t, resident_mib()});
      sample.slam_map_mib = flight_.telemetry().slam_map_mib;
      rss_.push_back(sample);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

void SoakWatch::sample_flight(double t) {
  const DroneTruth truth = drone_.truth();
  const FlightTelemetry telemetry = flight_.telemetry();
  const std::string activity = drone_activity(truth, telemetry);
  std::lock_guard lock(mutex_);
  // On the ground too, and kept across landings: a crash on take-off may come of the flight before.
  trail_.push_back(trail_point(t, truth, telemetry));
  while (!trail_.empty() && trail_.front().t_s < t - kTrailS) trail_.pop_front();
  // A battery swap brings a new lab whose count starts again.
  if (truth.crashes < lab_crashes_) crashes_before_ += lab_crashes_;
  if (truth.crashes > lab_crashes_) {
    std::cerr << "[soak " << static_cast<int>(t) << " s] CRASH: the drone hit " << truth.crash_reason << " ("
              << "link " << telemetry.link_state << ")" << std::endl;
    crash_reports_.push_back({t, truth.crash_reason, telemetry.mission, {trail_.begin(), trail_.end()}});
  }
  lab_crashes_ = truth.crashes;
  if (activity != "flying without a mission") {
    unmanaged_since_ = -1;
  } else if (unmanaged_since_ < 0) {
    unmanaged_since_ = t;
  } else {
    longest_unmanaged_ = std::max(longest_unmanaged_, t - unmanaged_since_);
  }
}

double SoakWatch::longest_unmanaged_flight_s() const {
  std::lock_guard lock(mutex_);
  return longest_unmanaged_;
}

int SoakWatch::crashes() const {
  std::lock_guard lock(mutex_);
  return crashes_before_ + lab_crashes_;
}

std::vector<CrashReport> SoakWatch::crash_reports() const {
  std::lock_guard lock(mutex_);
  return crash_reports_;
}

std::vector<RssSample> SoakWatch::rss() const {
  std::lock_guard lock(mutex_);
  return rss_;
}

}  // namespace labo::bench
