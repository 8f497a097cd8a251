#include <catch2/catch.hpp>

#include "localization/planar/sequence_bench.hpp"

using namespace labo;

// The simulated lab's oscilloscope approached from 3 m to 0.6 m, rendered by the lab's own renderer
// (the `bench planar` sequence). At 2.3-2.4 m the panel (~97 px wide) is tracked on the 80 px
// template level, coarser than the frame, and IC's full Gauss-Newton steps used to cycle across the
// minimum until the iteration limit: 5 losses for no convergence, each restarting the pose filter.
TEST_CASE("planar: the lab's oscilloscope is tracked from 3 m to 0.6 m without a loss") {
  const SequenceBenchResult result =
      run_sequence_bench(PlanarConfig{}, VisionThresholds{}, "lab_renderer", {TrackerKind::InverseCompositional});
  REQUIRE(result.sequences.size() == 1);
  const SequenceStats& s = result.sequences.front();
  CHECK(s.losses == 0);
  CHECK(s.detections == 1);
  CHECK(s.frames_with_pose == s.frames_in_view);
}
