#pragma once
// Missions flown in real time through the same threads as `labodrone serve --drone sim`: the
// simulated lab under the AR.Drone 2.0 emulator on loopback, the real driver, FlightRuntime with its
// vision worker, on the wall clock. Where the lockstep campaigns measure the flight software with
// time stopped, these measure what the server does with it: whether the mission succeeds while the
// front-ends compete with rendering, encoding and the link for two cores, and how the control loop
// keeps time (tick interval, capture-to-estimate latency, frames skipped).
#include <string>
#include <vector>

#include "server/runtime/runtime_timing.hpp"

namespace labo::bench {

using server::RuntimeTimingSummary;


enum class RealtimeMission { Inspect, FindTeacher };

struct RealtimeCampaignOptions {
  RealtimeMission mission = RealtimeMission::Inspect;
  std::string config_file;      // the app's configuration (config/default.json)
  unsigned seed = 1;            // run i flies the simulated lab with seed + i
  int runs = 1;
  std::string instrument;       // inspect: empty = the lab's first
  double hold_s = 5.0;          // inspect: the hold in front of the panel
  double follow_s = 20.0;       // find teacher: how long to follow once found
  double min_following = 0.9;   // find teacher: the share of that time the face must be followed
  double timeout_s = 180.0;     // a run that has not ended by then fails
  // Missions flown one after another on one server, as students taking turns: the SLAM map, the
  // battery and where the drone came down are kept between them. Inspect without `instrument` takes
  // the lab's instruments in turn.
  int in_a_row = 1;
  // When set, a CSV of every mission: the telemetry five times a second (stage, localization source,
  // SLAM state, the estimate beside the simulated lab's truth) and each log line as it came.
  std::string trace_file;
};

struct RealtimeRun {
  unsigned seed = 0;
  int round = 0;                 // the mission's place in its server's row (0 first)
  std::string instrument;        // inspect: the instrument flown to
  bool success = false;
  std::string result;            // the mission's last word, or why the run failed
  double duration_s = 0;         // wall time from the request to the end
  double landing_error_m = -1;   // inspect: true distance to the platform's centre after landing
  bool landed = false;
  // find teacher: the share of the follow's time in stage "3 face-follow" itself (the face followed,
  // not its lost phases or a new search), sampled every 50 ms
  double following = 0;
  RuntimeTimingSummary timing;  // the server's, from its start to this mission's end
};

// Flies the runs one after another, `in_a_row` missions each. Throws ConfigError / std::runtime_error for a configuration or
// lab that cannot be flown.
std::vector<RealtimeRun> run_realtime_campaign(const RealtimeCampaignOptions& options);

}  // namespace labo::bench
