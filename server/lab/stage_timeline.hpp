#pragma once
// The mission's progress as the student's page shows it: a timeline of the mission's stages, each
// with when it started, how long it ran and what the drone waits for (the mission's own words:
// "waiting for scale: 2/3 pairs", "searching for 'oscilloscope': placed 4/10 detections", "holding
// 4.2 s of 10 s at 0.8 m"), ending with the mission's result. StageTimeline builds it from the flight
// software's progress at every control tick. A stage is the mission's numbered stage ("3 inspect");
// its sub-steps (approach, hold, re-detect) change only what it waits for. Times are the caller's
// (the runtime gives Unix seconds).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace labo::server {

// What the flight software reports of its mission at a tick.
struct MissionProgress {
  std::string mission = "idle";  // "inspect", "find_teacher", "return_home"; anything without stages: none runs
  int stage_index = 0;           // 1..stage_count
  int stage_count = 0;           // 0: no staged mission runs
  std::string stage;             // "3 inspect: holding 4.2 s of 10 s at 0.8 m"
  int missions_ended = 0;        // a change: a mission has ended, with last_result
  std::string last_result;       // "succeeded: ...", "failed: ...", "emergency stop", "land requested", ...
};

// A stage line split into its name and what it waits for: "3 inspect: holding ..." -> {"inspect",
// "holding ..."}; "6 landing" -> {"landing", ""}. The leading number is dropped (the index is reported
// apart).
struct StageWords {
  std::string name;
  std::string waiting_for;
};
StageWords split_stage_line(const std::string& line);

struct TimelineStage {
  int index = 0;
  std::string name;
  Seconds started = 0;
  std::optional<Seconds> ended;
  std::string waiting_for;  // now; once ended, its last words
};

struct MissionTimeline {
  std::string mission;  // empty: no mission has run yet
  int stage_count = 0;
  Seconds started = 0;
  std::optional<Seconds> ended;
  std::string result;  // once ended: how (the flight software's words)
  bool succeeded = false;
  std::vector<TimelineStage> stages;  // oldest first, at most StageTimeline::kMaxStages
  int dropped = 0;                    // older stages dropped to keep that bound
};

class StageTimeline {
 public:
  // A mission bouncing between two stages (re-detection, face lost and found) keeps its latest.
  static constexpr std::size_t kMaxStages = 24;

  // One tick's progress; true when a stage or the mission began or ended (not when only the words of
  // the current stage changed).
  bool observe(Seconds t, const MissionProgress& progress);
  const MissionTimeline& timeline() const { return timeline_; }

 private:
  void end_mission(Seconds t, const std::string& result);
  bool enter_stage(Seconds t, int index, const StageWords& words);

  MissionTimeline timeline_;
  std::optional<int> missions_ended_;
};

}  // namespace labo::server
