#pragma once
// What a soak of `labodrone serve` under faults found (SoakSummary) and the checks it must pass
// (soak_failures): the server stayed up, the drone was never left flying without a mission, every
// fault was applied, the recording is complete and replays to its end, and memory stayed flat after
// warm-up. The checks are a pure function of the summary, so their tests can feed bad summaries.
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "server/runtime/runtime_timing.hpp"

namespace labo::bench {

using server::RuntimeTimingSummary;


struct RssSample {
  double t_s = 0;
  double mib = 0;
  // The C library's heap: bytes in live allocations, and bytes it holds from the kernel (live or
  // free). RSS growing with the first flat is memory freed but kept (fragmentation), not a leak.
  double heap_in_use_mib = 0, heap_held_mib = 0;
  double slam_map_mib = 0;  // the flight software's SLAM map: bounded by slam.max_keyframes
};

// One fault and the drone's state once it was over and the flight software had time to act.
struct FaultRecord {
  std::string kind;        // link_cut, emulator_restart, low_battery
  double at_s = 0;         // since the start of the soak
  double duration_s = 0;   // the cut or the time the emulator was down (low battery: the round)
  bool airborne = false;   // when it began
  std::string after;       // landed | mission <name> | flying without a mission
  std::string detail;      // the mission's end, when it ended meanwhile
};

// One moment of the flight as the watch saw it: the lab's truth beside what the flight software
// believed and wanted (world frame, metres and degrees).
struct TrailPose {
  double x_m = 0, y_m = 0, z_m = 0, yaw_deg = 0;
};

struct TrailPoint {
  double t_s = 0;
  TrailPose truth, estimate;
  std::optional<TrailPose> desired;  // none without a set point
  std::string source, slam, stage, link;
};

// A crash and the flight that led to it, so that a failed soak says why without a rerun.
struct CrashReport {
  double at_s = 0;
  std::string hit;      // what the hull hit
  std::string mission;  // the mission running, "idle" when none
  std::vector<TrailPoint> trail;  // the seconds before the crash, oldest first
};

struct SoakSummary {
  double duration_s = 0;
  // The server.
  int health_probes = 0, health_failures = 0;
  std::uint64_t http_5xx = 0;
  // The drone.
  std::vector<FaultRecord> faults;
  double longest_unmanaged_flight_s = 0;  // airborne with no mission running (truth + telemetry)
  bool ended_landed = false;
  int crashes = 0;
  std::vector<CrashReport> crash_reports;
  int battery_swaps = 0;
  int set_downs = 0;  // a drone landed with its place unconfirmed, set on its platform by the admin
  // Missions (rounds).
  int rounds = 0, missions_accepted = 0, missions_succeeded = 0, missions_refused = 0;
  std::vector<std::string> mission_results;  // the mission's last word per round
  // Clients.
  std::uint64_t logins = 0, ws_connections = 0, spectators_joined = 0, slow_reader_stalls = 0;
  std::uint64_t slow_reader_cut_off = 0;       // the server closed the slow reader's connection
  std::uint64_t frames_sent = 0, frames_received = 0;  // server: JPEG frames + H.264 units written
  std::uint64_t frames_skipped = 0, slow_disconnects = 0;
  // The recording.
  std::uint64_t recording_reported_bytes = 0, recording_file_bytes = 0;
  std::uint64_t replay_records = 0, replay_navdata = 0, replay_frames = 0;
  bool replay_to_end = false;
  std::string replay_error;
  // Memory, from /proc/self/status (VmRSS).
  int rss_samples = 0;
  double warmup_s = 0;
  double rss_warmup_peak_mib = 0, rss_after_peak_mib = 0, rss_final_mib = 0;
  double rss_growth_percent = 0;  // after-warm-up peak over the warm-up's peak
  // The same without the SLAM map: a map filling up to slam.max_keyframes is bounded growth the
  // warm-up may not cover (~0.4 MiB a keyframe); what is left is what a leak would show.
  double net_warmup_peak_mib = 0, net_after_peak_mib = 0, net_peak_growth_percent = 0;
  // What the memory check judges: the level of RSS less the map, not its peaks (a peak is whichever
  // mission was flying at a sample, a solve or a burst of frames in use). The median over the
  // warm-up's second half against the median over the run's last quarter: a leak raises the second.
  double net_warmup_level_mib = 0, net_end_level_mib = 0, net_growth_percent = 0;
  // The heap's live bytes less the map, their peaks in the same two spans: a peak of RSS that the
  // live bytes share is a transient in use (a buffer, a solve); one they do not is memory the C
  // library held after it was freed.
  double in_use_net_warmup_peak_mib = 0, in_use_net_after_peak_mib = 0;
  std::vector<double> slam_map_per_minute_mib;
  std::vector<double> rss_per_minute_mib;  // the last sample of each minute: where the growth went
  // The same minutes as the heap sees them: in live allocations, and held from the kernel.
  std::vector<double> heap_in_use_per_minute_mib, heap_held_per_minute_mib;
  // The flight thread's timing over the whole soak.
  RuntimeTimingSummary timing;
};

struct SoakLimits {
  double rss_growth_percent = 5.0;
  double unmanaged_flight_s = 15.0;  // longer without a mission: the drone was left flying
  int link_cuts = 2, emulator_restarts = 1, low_battery = 1;
};

// The memory figures of the summary from the samples of a run of total_s seconds.
void summarise_memory(const std::vector<RssSample>& rss, double total_s, SoakSummary& s);

// The checks of the service: the server stayed up, every fault was applied, clients got frames, the
// recording is complete and replays, memory stayed flat.
std::vector<std::string> service_failures(const SoakSummary& summary, const SoakLimits& limits);
// The checks of the flight under the faults: the drone landed or held after each, never flew long
// without a mission, landed at the end, never crashed, landed on the low battery.
std::vector<std::string> flight_failures(const SoakSummary& summary, const SoakLimits& limits);
// Both: every check that failed, in words; empty when the soak passed.
std::vector<std::string> soak_failures(const SoakSummary& summary, const SoakLimits& limits);

nlohmann::json to_json(const SoakSummary& summary, const std::vector<std::string>& failures);
std::string to_text(const SoakSummary& summary, const std::vector<std::string>& failures);

}  // namespace labo::bench
