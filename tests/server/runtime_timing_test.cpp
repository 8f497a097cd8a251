#include <catch2/catch.hpp>

#include "localization/fusion/vision_job.hpp"
#include "server/runtime/runtime_timing.hpp"

using namespace labo;
using namespace labo::server;

TEST_CASE("runtime timing: the vision latency of frames with a target tracked is kept apart from a search's") {
  RuntimeTiming timing(16);
  // A search: full-frame detections, slow; then tracking, fast.
  for (int i = 0; i < 5; ++i) timing.add_vision(200.0, 190.0, false);
  for (int i = 0; i < 10; ++i) timing.add_vision(10.0 + i, 5.0, true);
  const RuntimeTimingSummary s = timing.summary();
  CHECK(s.vision_latency_ms.count == 15);
  CHECK(s.vision_latency_ms.max == 200.0);
  CHECK(s.vision_latency_tracking_ms.count == 10);
  CHECK(s.vision_latency_tracking_ms.median == Approx(15.0));  // 10..19: the 5th of 0..9 rounded up
  CHECK(s.vision_latency_tracking_ms.max == 19.0);
}

TEST_CASE("runtime timing: a frame counts as tracking when any target of its results is tracked") {
  fusion::VisionResults r;
  CHECK_FALSE(r.tracking());
  r.has_slam = true;  // SLAM alone is no target
  CHECK_FALSE(r.tracking());
  r.has_face = true;
  r.face.state = fusion::TrackState::Searching;
  CHECK_FALSE(r.tracking());
  r.face.state = fusion::TrackState::Tracking;
  CHECK(r.tracking());
  r.face.state = fusion::TrackState::Lost;
  r.has_platform = true;
  r.platform.state = fusion::TrackState::Tracking;
  CHECK(r.tracking());
  r.has_platform = false;  // a stale observation of a target not in the job
  CHECK_FALSE(r.tracking());
}
