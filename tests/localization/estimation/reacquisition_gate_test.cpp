#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/config_reader.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/reacquisition_gate.hpp"
#include "localization/estimation/state_estimator.hpp"
#include "synthetic_flight.hpp"

using namespace labo;
using namespace labo::estimation;
using labo::test::DelayedLink;
using labo::test::SyntheticFlight;

namespace {
constexpr Seconds kFrame = 1.0 / 30.0;
constexpr Seconds kGap = 0.4;
}  // namespace

TEST_CASE("estimation: the re-acquisition gate refuses a 1 m jump and accepts a small one") {
  estimation::ReacquisitionGate gate;
  // 1 m off, although a grown covariance makes it look plausible (d2 = 4).
  CHECK(gate.check({1.0, 0, 0, 0}, 4.0, 0.0, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
  CHECK(gate.refused_in_row() == 1);
  // Within both bounds: accepted, and the source stays accepted while it keeps coming.
  estimation::ReacquisitionGate near;
  CHECK(near.check({0.1, -0.05, 0.02, 0.01}, 2.0, 0.0, kGap) == estimation::ReacquisitionGate::Verdict::Accepted);
  CHECK(near.open());
  // Small in metres but improbable under a tight covariance: refused.
  estimation::ReacquisitionGate tight;
  CHECK(tight.check({0.2, 0, 0, 0}, 100.0, 0.0, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
}

TEST_CASE("estimation: a consistent re-detection is accepted after confirm_frames, an erratic one never") {
  estimation::ReacquisitionSettings s;
  s.confirm_frames = 10;
  SECTION("consistent: the same 1 m offset every frame") {
    estimation::ReacquisitionGate gate(s);
    for (int i = 0; i < 9; ++i)
      REQUIRE(gate.check({1.0 + 0.01 * (i % 2), 0.0, 0.0, 0.0}, 50.0, i * kFrame, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
    CHECK(gate.check({1.0, 0.0, 0.0, 0.0}, 50.0, 9 * kFrame, kGap) == estimation::ReacquisitionGate::Verdict::Confirmed);
    CHECK(gate.check({1.0, 0.0, 0.0, 0.0}, 50.0, 10 * kFrame, kGap) == estimation::ReacquisitionGate::Verdict::Accepted);
    // Lost for longer than the gap: the next pose is checked anew.
    CHECK(gate.check({1.0, 0.0, 0.0, 0.0}, 50.0, 10 * kFrame + 1.0, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
  }
  SECTION("erratic: the offset jumps 0.3 m from frame to frame") {
    estimation::ReacquisitionGate gate(s);
    for (int i = 0; i < 60; ++i)
      CHECK(gate.check({1.0 + 0.3 * (i % 2), 0.0, 0.0, 0.0}, 50.0, i * kFrame, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
  }
  SECTION("a gap breaks the run") {
    estimation::ReacquisitionGate gate(s);
    for (int i = 0; i < 9; ++i) gate.check({1.0, 0.0, 0.0, 0.0}, 50.0, i * kFrame, kGap);
    CHECK(gate.check({1.0, 0.0, 0.0, 0.0}, 50.0, 9 * kFrame + 0.5, kGap) == estimation::ReacquisitionGate::Verdict::Refused);
    CHECK(gate.refused_in_row() == 1);
  }
}

namespace {
// Hovers a synthetic drone in front of an object, loses the object for `lost_s`, then delivers a
// re-detection `offset` off the truth for `frames` frames; returns the estimator.
struct Redetection {
  SyntheticFlight truth{11};
  estimation::StateEstimator est;
  DelayedLink link{truth, 0.0, 0.0, 1.0 / 200.0, {}, {}, 0.0};
  Eigen::Isometry3d T_world_object = make_pose({2.0, 0.1, 1.1}, 0.0) *
                                     Eigen::Isometry3d(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()) *
                                                       Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  std::mt19937 rng{5};
  Seconds next_frame = 0.0;
  bool visible = true;
  Eigen::Vector3d offset_world = Eigen::Vector3d::Zero();  // the re-detection's error, in the world

  explicit Redetection(const estimation::EstimatorConfig& c) : est(c) { est.reset(truth.T_world_body(), 0.0); }

  void run_until(Seconds t) {
    std::normal_distribution<double> n(0.0, 0.003);
    link.run_until(t, [&](const NavdataSample& nav) {
      est.add_navdata(nav);
      if (truth.t < next_frame) return;
      next_frame += kFrame;
      if (!visible) return;
      estimation::ObjectObservation o;
      o.t = truth.t;
      o.object_index = 1;
      // Seen from a camera displaced by offset_world: the implied body pose is off by that much.
      Eigen::Isometry3d T_world_cam = truth.T_world_body() * T_body_cam_front();
      T_world_cam.translation() += offset_world;
      o.T_cam_object = T_world_cam.inverse() * T_world_object;
      o.T_cam_object.translation() += Eigen::Vector3d(n(rng), n(rng), n(rng));
      o.T_world_object_surveyed = T_world_object;
      est.add_object_pose(o);
    });
  }
  double error() { return (est.predict(truth.t).position_world - truth.s().segment<3>(est::X)).norm(); }
};

estimation::EstimatorConfig no_delays() {
  estimation::EstimatorConfig c;
  c.video_delay_s = c.navdata_delay_s = c.control_delay_s = 0.0;
  return c;
}
}  // namespace

TEST_CASE("estimation: a wrong re-detection 1 m off after a loss does not drive the estimate") {
  estimation::EstimatorConfig c = no_delays();
  c.reacquisition.confirm_frames = 15;
  Redetection r(c);
  r.run_until(3.0);  // placed and tracked
  REQUIRE(r.est.source() == estimation::LocalizationSource::Homography);
  r.visible = false;
  r.run_until(7.0);  // 4 s of dead reckoning
  REQUIRE(r.est.source() == estimation::LocalizationSource::DeadReckoning);
  const double before = r.error();
  // The panel re-detected 1 m off along x, erratic by 0.3 m from frame to frame (a wrong homography).
  r.visible = true;
  std::uint64_t refused = 0;
  for (int i = 0; i < 30; ++i) {
    r.offset_world = Eigen::Vector3d(-1.0 + 0.3 * (i % 2), 0.0, 0.0);
    r.run_until(7.0 + (i + 1) * kFrame);
  }
  refused = r.est.statistics().count("rejected_reacquisition");
  CHECK(refused >= 25);
  CHECK(r.est.statistics().count("reacquisition_confirmed") == 0);
  CHECK(r.est.source() == estimation::LocalizationSource::DeadReckoning);
  CHECK(r.error() < before + 0.1);  // still dead reckoning, not dragged 1 m
}

TEST_CASE("estimation: a re-detection that persists with one offset is accepted after confirm_frames") {
  estimation::EstimatorConfig c = no_delays();
  c.reacquisition.confirm_frames = 15;
  Redetection r(c);
  r.run_until(3.0);
  r.visible = false;
  r.run_until(5.0);
  // The estimate is the one that is wrong here: the panel says the drone is 0.8 m from where the
  // filter thinks; consistent frames must win after confirm_frames.
  r.visible = true;
  r.offset_world = Eigen::Vector3d(0.8, 0.0, 0.0);
  r.run_until(5.0 + 10 * kFrame);
  INFO("refused " << r.est.statistics().count("rejected_reacquisition") << " confirmed "
                  << r.est.statistics().count("reacquisition_confirmed") << " fused " << r.est.statistics().count("object_fused"));
  CHECK(r.est.statistics().count("rejected_reacquisition") >= 9);
  CHECK(r.est.source() == estimation::LocalizationSource::DeadReckoning);
  r.run_until(6.5);
  CHECK(r.est.statistics().count("reacquisition_confirmed") == 1);
  CHECK(r.est.source() == estimation::LocalizationSource::Homography);
  // Fused: the estimate follows the vision (0.8 m from the truth, by construction).
  const Eigen::Vector3d p = r.est.predict(r.truth.t).position_world;
  INFO("estimate - truth " << (p - r.truth.s().segment<3>(est::X)).transpose() << " fused " << r.est.statistics().count("object_fused")
       << " gated " << r.est.statistics().count("rejected_innovation") << " jump " << r.est.statistics().count("rejected_jump_distance"));
  CHECK((p - (r.truth.s().segment<3>(est::X) + r.offset_world)).norm() < 0.1);
}

TEST_CASE("estimation: a re-detection that agrees with the estimate is fused at once") {
  Redetection r(no_delays());
  r.run_until(3.0);
  r.visible = false;
  r.run_until(4.0);
  r.visible = true;
  r.run_until(4.5);
  CHECK(r.est.statistics().count("rejected_reacquisition") == 0);
  CHECK(r.est.source() == estimation::LocalizationSource::Homography);
}

TEST_CASE("estimation: the re-acquisition gate is configured in the estimation section, bad values refused") {
  const ConfigDocument doc = ConfigDocument::parse(
      R"({"reacquisition": {"chi2": 9.0, "max_jump_m": 0.3, "confirm_frames": 20, "confirm_spread_m": 0.05}})", "t.json");
  const estimation::EstimatorConfig c = estimation::read_estimation_config(doc.root());
  CHECK(c.reacquisition.chi2 == Approx(9.0));
  CHECK(c.reacquisition.max_jump_m == Approx(0.3));
  CHECK(c.reacquisition.confirm_frames == 20);
  CHECK(c.reacquisition.confirm_spread_m == Approx(0.05));
  for (const char* bad : {R"({"reacquisition": {"chi2": 0}})", R"({"reacquisition": {"max_jump_m": 0.0}})",
                          R"({"reacquisition": {"confirm_frames": 0}})", R"({"reacquisition": {"confirm_spread_m": 5}})"}) {
    INFO(bad);
    CHECK_THROWS(estimation::read_estimation_config(ConfigDocument::parse(bad, "bad.json").root()));
  }
  CHECK_THROWS_WITH(estimation::read_estimation_config(ConfigDocument::parse(R"({"reacquisition": {"max_jump": 1}})", "u.json").root()),
                    Catch::Contains("max_jump"));
}
