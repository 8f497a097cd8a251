#include <catch2/catch.hpp>
#include <cmath>

#include "bench/experiments/experiment_common.hpp"
#include "bench/experiments/sim_lab_flight.hpp"
#include "core/source_tree.hpp"

using namespace labo;
using namespace labo::bench;

// The inspect mission in the simulated lab with rendered cameras and the real vision pipelines: it
// must reach the 0.80 m hold in front of the oscilloscope's panel, centred, on the panel's homography.
TEST_CASE("control: real vision in the simulated lab reaches the 0.80 m hold in front of the panel") {
  ExperimentOptions o;
  o.config = labo::source_root() / "config" / "default.json";
  o.real_vision = true;
  o.video_fps = 15;  // half the drone's 30 fps keeps this test short; `sim inspect --vision real` runs 30
  const Experiment e = make_experiment(o, false);
  REQUIRE(e.lab);
  const auto f = make_flight(e, 1);
  const fusion::PlanarTarget& osc = *e.setup.lab.find_instrument("oscilloscope");
  control::MissionRequest r;
  r.kind = control::RequestKind::Inspect;
  r.instrument_id = osc.id;
  r.hold_s = 2;
  REQUIRE(f->request(r).accepted);
  // The errors over the hold's last second (30 ticks), as `labodrone-bench sim inspect` measures them.
  std::vector<double> standoff, centre;
  std::vector<fusion::FeedbackSource> sources;
  const bool held = f->run_until([&] {
    const control::FlightStatus s = f->stack().status();
    if (s.stage.find("holding") != std::string::npos) {
      const Eigen::Vector3d p = f->true_T_cam(osc.T_world_object).translation();
      standoff.push_back(std::abs(p.z() - 0.80));
      centre.push_back(centre_offset_fraction(p, e.setup.cameras.front));
      sources.push_back(s.source);
    }
    return s.stage_index >= 4 || s.mission == "idle";  // the hold is over
  }, 70.0);
  const control::FlightStatus s = f->stack().status();
  INFO("stage: " << s.stage << "; last event: " << s.last_event << "; SLAM " << to_string(s.slam.state)
                 << "; instrument " << to_string(s.instrument.state) << " " << s.instrument.reason << "; t " << f->now());
  REQUIRE(held);
  REQUIRE(standoff.size() >= 30);
  const auto last_second = [](const std::vector<double>& v) { return std::vector<double>(v.end() - 30, v.end()); };
  CHECK(rms(last_second(standoff)) < 0.05);
  CHECK(rms(last_second(centre)) < 0.05);
  CHECK(s.stage_index == 4);  // held the full 2 s, then left on its own
  CHECK(sources.back() == fusion::FeedbackSource::Homography);
  CHECK_FALSE(f->crashed());
}
