#include <catch2/catch.hpp>

#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;
using namespace labo::bench;  // the synthetic room and its flights

TEST_CASE("slam: tracks a short synthetic approach against ground truth") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSystem slam(camera, testing::synchronous());
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 10.0);
  const auto run = testing::run(slam, room, frames);
  // Initialization takes about 2 s (the climb); everything after it is tracked.
  CHECK(run.tracked.size() > frames.size() / 2);
  CHECK(testing::tracked_fraction_after_init(run) > 0.98);
  const auto errors = trajectory_errors(run.tracked);
  REQUIRE(errors);
  INFO("ATE " << errors->ate_rmse_m * 100 << " cm over " << errors->poses << " poses");
  CHECK(errors->ate_rmse_m < 0.03);
  CHECK(slam.status().keyframes > 2);
}

TEST_CASE("slam: threaded mapping tracks the same sequence") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSettings settings;
  settings.mapping_mode = MappingMode::Threaded;
  SlamSystem slam(camera, settings);
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 8.0);
  const auto run = testing::run(slam, room, frames);
  slam.wait_for_mapping();
  CHECK(run.tracked.size() > frames.size() / 2);
  CHECK(testing::tracked_fraction_after_init(run) > 0.95);
  const auto errors = trajectory_errors(run.tracked);
  REQUIRE(errors);
  CHECK(errors->ate_rmse_m < 0.05);
}

TEST_CASE("slam: synchronous mode is deterministic") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 5.0);
  SlamSystem a(camera, testing::synchronous()), b(camera, testing::synchronous());
  const auto ra = testing::run(a, room, frames);
  const auto rb = testing::run(b, room, frames);
  REQUIRE(ra.tracked.size() == rb.tracked.size());
  REQUIRE_FALSE(ra.tracked.empty());
  CHECK(ra.tracked.back().estimate_T_map_cam.isApprox(rb.tracked.back().estimate_T_map_cam, 1e-12));
}

TEST_CASE("slam: trajectory metrics recover a known similarity") {
  std::vector<PosePair> pairs;
  Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
  S.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  S.translation() = Eigen::Vector3d(1, 2, 3);
  for (int i = 0; i < 100; ++i) {
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
    truth.translation() = Eigen::Vector3d(std::cos(i * 0.1), std::sin(i * 0.1), 0.01 * i);
    Eigen::Isometry3d est = S * truth;
    est.translation() *= 0.5;  // unknown monocular scale
    pairs.push_back({i * 0.1, est, truth});
  }
  const auto e = trajectory_errors(pairs);
  REQUIRE(e);
  CHECK(e->ate_rmse_m < 1e-9);
  CHECK(e->alignment_scale == Approx(2.0));
  CHECK(e->scale_drift_percent < 1e-6);
  CHECK(e->rpe_translation_rmse_m < 1e-9);
}
