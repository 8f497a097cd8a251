// The inspect mission flown as a Tello in lockstep (SimTelloLink, `--drone-model tello`) with the
// shipped config and the real vision front-ends: what a Tello's flight must do from take-off to
// landing on the platform, found with the Tello EDU's downward camera (downvision) as the AR.Drone
// finds it with its bottom camera, within the campaign's 0.10 m.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench/experiments/experiment_common.hpp"
#include "bench/experiments/sim_lab_flight.hpp"
#include "core/source_tree.hpp"
#include "drone/sim/sim_tello_link.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// The take-off's manoeuvre gives SLAM's map its scale in one round: with the estimation section's
// 0.1 s navdata gap limit every scale pair of a 10 Hz state was dropped and the manoeuvre repeated
// ("again: no scale yet") until the flight went on dead reckoning; tello.estimation's 0.15 s fixes it.
TEST_CASE("control: a Tello in the simulated lab scales its map in one round then holds at the panel and lands on the platform with its downward camera") {
  ExperimentOptions o;
  o.config = labo::source_root() / "config" / "default.json";
  o.real_vision = true;
  o.tello = true;
  o.world = WorldMode::Nominal;
  o.video_fps = 15;  // half the Tello's 30 fps keeps this test short
  const Experiment e = make_experiment(o, false);
  REQUIRE(e.tello);
  CHECK(e.setup.cameras.front.width == 960);  // tello.camera
  CHECK(e.setup.estimation.scale_max_navdata_gap_s == Approx(0.15));  // tello.estimation
  const auto f = make_flight(e, 1);
  const auto* sim = dynamic_cast<const SimLabFlight*>(f.get());
  REQUIRE(sim);
  const fusion::PlanarTarget& osc = *e.setup.lab.find_instrument("oscilloscope");
  control::MissionRequest r;
  r.kind = control::RequestKind::Inspect;
  r.instrument_id = osc.id;
  r.hold_s = 2;
  REQUIRE(f->request(r).accepted);

  const double resting_z_m = f->true_pose().translation().z();  // the body's origin on the platform
  double highest_m = 0;
  bool repeated = false, scaled_in_init = false, scale_lost = false;
  bool scaled = false;
  std::vector<double> standoff;  // |camera-to-panel distance - 0.80| while holding, true poses
  const bool ended = f->run_until([&] {
    const control::FlightStatus s = f->stack().status();
    highest_m = std::max(highest_m, f->true_pose().translation().z());
    repeated = repeated || contains(s.stage, "again");
    if (s.stage_index == 1 && s.slam.scale_estimated) scaled_in_init = true;
    scale_lost = scale_lost || (scaled && !s.slam.scale_estimated);
    scaled = scaled || s.slam.scale_estimated;
    if (contains(s.stage, "holding")) standoff.push_back(std::abs(f->true_T_cam(osc.T_world_object).translation().z() - 0.80));
    return s.mission == "idle";
  }, 200.0);
  const control::FlightStatus s = f->stack().status();
  INFO("stage: " << s.stage << "; last event: " << s.last_event << "; t " << f->now());
  REQUIRE(ended);
  // Take-off: SDK mode, "takeoff" answered, the drone up at the manoeuvre's height.
  CHECK(highest_m > 0.8);
  // The scale: fixed during the take-off stage, in its first round, and kept.
  CHECK_FALSE(repeated);
  CHECK(scaled_in_init);
  CHECK_FALSE(scale_lost);
  // The panel: reached and held, the standoff within the campaign's 0.10 m over the hold's last second.
  REQUIRE(standoff.size() >= 30);  // 30 control ticks a second
  for (std::size_t i = standoff.size() - 30; i < standoff.size(); ++i) CHECK(standoff[i] < 0.10);
  // The landing: the platform found with the downward camera, landed on within the campaign's 0.10 m.
  CHECK(contains(s.last_event, "succeeded"));
  CHECK_FALSE(contains(s.last_event, "landing at the estimated base"));
  CHECK(s.phase == control::FlightPhase::Landed);
  CHECK(f->true_pose().translation().z() < resting_z_m + 0.05);
  const double landing_m =
      (f->true_pose().translation() - f->true_lab().lab.platform.T_world_object.translation()).head<2>().norm();
  CHECK(landing_m < 0.10);
  CHECK_FALSE(f->crashed());
  const LinkStatistics link = sim->link().statistics();
  CHECK_FALSE(link.counters.contains("tello_bottom_camera_unavailable"));
  CHECK_FALSE(link.counters.contains("tello_downvision_refused"));
  CHECK_FALSE(link.counters.contains("reconnects"));  // the state never went silent for 2 s
}
