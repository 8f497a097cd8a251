#pragma once
// The soak's observer, on its own thread: five times a second the lab's truth beside the flight
// software's telemetry (how long the drone has flown with no mission running; the last seconds of
// the flight, kept for a crash's report), every few seconds a health probe over HTTP and the
// process's resident memory (VmRSS of /proc/self/status).
#include <atomic>
#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bench/soak/restartable_drone.hpp"
#include "bench/soak/soak_report.hpp"
#include "server/lab/flight_service.hpp"

namespace labo::bench {

using server::FlightService;
using server::FlightTelemetry;

// VmRSS of this process in MiB (0 when /proc is not there).
double resident_mib();
// `sample` with the heap's two figures filled in (mallinfo2, every arena).
RssSample with_heap_figures(RssSample sample);

// The watch's view of one moment: `truth` beside `telemetry` at `t_s`.
TrailPoint trail_point(double t_s, const DroneTruth& truth, const FlightTelemetry& telemetry);

// What the drone is doing, in the words of the checks: "landed", "mission <name>", or "flying
// without a mission".
std::string drone_activity(const DroneTruth& truth, const FlightTelemetry& telemetry);

class SoakWatch {
 public:
  SoakWatch(RestartableDrone& drone, FlightService& flight, unsigned short port, double probe_every_s);
  ~SoakWatch();
  void stop();

  double elapsed_s() const;
  double longest_unmanaged_flight_s() const;
  int health_probes() const { return probes_; }
  int health_failures() const { return probe_failures_; }
  int crashes() const;
  std::vector<CrashReport> crash_reports() const;
  std::vector<RssSample> rss() const;

  static constexpr double kTrailS = 60.0;  // kept before a crash, landed or not (the flight before a take-off included)

 private:
  void run();
  void sample_flight(double t);

  RestartableDrone& drone_;
  FlightService& flight_;
  unsigned short port_;
  double probe_every_s_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::atomic<bool> running_{true};
  std::atomic<int> probes_{0}, probe_failures_{0};
  mutable std::mutex mutex_;
  double unmanaged_since_ = -1, longest_unmanaged_ = 0;
  int crashes_before_ = 0, lab_crashes_ = 0;
  std::deque<TrailPoint> trail_;
  std::vector<CrashReport> crash_reports_;
  std::vector<RssSample> rss_;
  std::thread thread_;
};

}  // namespace labo::bench
