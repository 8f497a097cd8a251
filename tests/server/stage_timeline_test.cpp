// The mission's stage timeline (server/lab/stage_timeline.hpp): stages begin and end with the
// mission's numbered stage, their words follow what the drone waits for, the mission ends with its
// result, and the timeline stays bounded.
#include <catch2/catch.hpp>

#include "server/lab/stage_timeline.hpp"

using namespace labo;
using namespace labo::server;

namespace {

MissionProgress inspect(int index, const std::string& stage, int ended = 0) {
  return {"inspect", index, 6, stage, ended, ""};
}

}  // namespace

TEST_CASE("stage timeline: a stage line splits into its name and what it waits for") {
  CHECK(split_stage_line("3 inspect: holding 4.2 s of 10 s at 0.8 m").name == "inspect");
  CHECK(split_stage_line("3 inspect: holding 4.2 s of 10 s at 0.8 m").waiting_for == "holding 4.2 s of 10 s at 0.8 m");
  CHECK(split_stage_line("1 init: scale manoeuvre (up): waiting for scale: 1/3 pairs").waiting_for ==
        "scale manoeuvre (up): waiting for scale: 1/3 pairs");
  CHECK(split_stage_line("6 landing").name == "landing");
  CHECK(split_stage_line("6 landing").waiting_for.empty());
  CHECK(split_stage_line("failed: link lost").name == "failed");
  CHECK(split_stage_line("42").name == "42");  // a bare number is no stage number
  CHECK(split_stage_line("").name.empty());
}

TEST_CASE("stage timeline: stages begin when the stage changes, their words follow every tick") {
  StageTimeline timeline;
  CHECK_FALSE(timeline.observe(0.0, {}));  // idle: nothing yet
  CHECK(timeline.timeline().mission.empty());
  CHECK(timeline.observe(1.0, inspect(1, "1 init: taking off")));
  CHECK_FALSE(timeline.observe(2.0, inspect(1, "1 init: scale manoeuvre (up): waiting for scale: 1/3 pairs")));
  const MissionTimeline& t = timeline.timeline();
  REQUIRE(t.stages.size() == 1);
  CHECK(t.mission == "inspect");
  CHECK(t.stage_count == 6);
  CHECK(t.started == 1.0);
  CHECK(t.stages[0].waiting_for == "scale manoeuvre (up): waiting for scale: 1/3 pairs");
  CHECK_FALSE(t.stages[0].ended);

  CHECK(timeline.observe(9.5, inspect(2, "2 detect: searching for 'oscilloscope': placed 0/10 detections (0.0 s)")));
  REQUIRE(t.stages.size() == 2);
  CHECK(t.stages[0].ended == 9.5);
  CHECK(t.stages[0].waiting_for == "scale manoeuvre (up): waiting for scale: 1/3 pairs");  // its last words stay
  CHECK(t.stages[1].index == 2);
  CHECK(t.stages[1].name == "detect");
  CHECK(t.stages[1].started == 9.5);
  // Approach, hold and re-detection are one stage: only its words change.
  CHECK(timeline.observe(12.0, inspect(3, "3 inspect: approaching 'oscilloscope' to 0.8 m")));
  CHECK_FALSE(timeline.observe(15.0, inspect(3, "3 inspect: holding 2.0 s of 10 s at 0.8 m")));
  CHECK(t.stages.size() == 3);
  CHECK(t.stages[2].waiting_for == "holding 2.0 s of 10 s at 0.8 m");
}

TEST_CASE("stage timeline: the mission ends with the flight software's result, and the next one starts anew") {
  StageTimeline timeline;
  timeline.observe(0.0, {});
  timeline.observe(1.0, inspect(5, "5 platform: searching with the bottom camera (1.0 s)"));
  timeline.observe(3.0, inspect(6, "6 landing"));
  CHECK(timeline.observe(5.0, {"idle", 0, 0, "", 1, "succeeded: inspected 'oscilloscope' for 10.0 s and landed on the platform"}));
  const MissionTimeline& t = timeline.timeline();
  CHECK(t.ended == 5.0);
  CHECK(t.succeeded);
  CHECK(t.result == "succeeded: inspected 'oscilloscope' for 10.0 s and landed on the platform");
  CHECK(t.stages.back().ended == 5.0);
  CHECK_FALSE(timeline.observe(6.0, {"idle", 0, 0, "", 1, "succeeded: ..."}));  // the ended mission stays shown

  timeline.observe(7.0, {"find_teacher", 1, 3, "1 init: taking off", 1, ""});
  CHECK(t.mission == "find_teacher");
  CHECK_FALSE(t.ended);
  CHECK(t.result.empty());
  REQUIRE(t.stages.size() == 1);
  CHECK(t.stages[0].started == 7.0);
}

TEST_CASE("stage timeline: a safety return home ends the mission and starts its own timeline in the same tick") {
  StageTimeline timeline;
  timeline.observe(0.0, inspect(3, "3 inspect: holding 1.0 s of 10 s at 0.8 m"));
  CHECK(timeline.observe(2.0, {"return_home", 1, 3, "4 return: climbing to the return altitude", 1, "safety: battery 12 %"}));
  const MissionTimeline& t = timeline.timeline();
  CHECK(t.mission == "return_home");
  CHECK_FALSE(t.ended);
  REQUIRE(t.stages.size() == 1);
  CHECK(t.stages[0].name == "return");
}

TEST_CASE("stage timeline: a failed mission and one ended without a result say so") {
  StageTimeline failed;
  failed.observe(0.0, inspect(2, "2 detect: searching"));
  failed.observe(20.0, {"idle", 0, 0, "", 1, "failed: instrument 'x' not detected in 15.0 s; returning home"});
  CHECK_FALSE(failed.timeline().succeeded);
  CHECK(failed.timeline().result.rfind("failed:", 0) == 0);

  // A core that counts no missions (a test double): the mission it reports next says how it ended.
  StageTimeline uncounted;
  uncounted.observe(0.0, inspect(2, "2 approach"));
  CHECK(uncounted.observe(1.0, {"emergency", 0, 0, "motors cut", 0, ""}));
  CHECK(uncounted.timeline().result == "emergency");
  CHECK_FALSE(uncounted.timeline().succeeded);
}

TEST_CASE("stage timeline: a mission bouncing between stages keeps the latest kMaxStages of them") {
  StageTimeline timeline;
  for (int i = 0; i < 40; ++i) timeline.observe(i, {"find_teacher", 2 + i % 2, 3, i % 2 ? "3 face-follow" : "2 search: yaw sweep", 0, ""});
  const MissionTimeline& t = timeline.timeline();
  CHECK(t.stages.size() == StageTimeline::kMaxStages);
  CHECK(t.dropped == 40 - static_cast<int>(StageTimeline::kMaxStages));
  CHECK(t.stages.back().started == 39.0);
  CHECK(t.started == 0.0);
}
