#include <catch2/catch.hpp>
#include <random>

#include "core/frames.hpp"
#include "localization/estimation/scale_estimator.hpp"
#include "localization/estimation/scale_pair_sampler.hpp"

using namespace labo;
using namespace labo::estimation;

TEST_CASE("estimation: ML scale reaches its two limits") {
  const double s_pp = 2.0, s_ii = 9.0, s_pi = 4.1;
  // Exact metric displacements: lambda = S_II / S_PI; exact map displacements: lambda = S_PI / S_PP.
  CHECK(estimation::ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 0.2, 1e-9) == Approx(s_ii / s_pi).epsilon(1e-6));
  CHECK(estimation::ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 1e-9, 0.2) == Approx(s_pi / s_pp).epsilon(1e-6));
  CHECK(estimation::ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 0.2, 0.2) > s_pi / s_pp);
}

TEST_CASE("estimation: scale estimator recovers the scale from noisy pairs with outliers") {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const double truth = 2.7;
  estimation::ScaleEstimator est{estimation::ScaleSettings{}};
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d p(0.05 * n(rng), 0.05 * n(rng), 0.4 * n(rng));
    Eigen::Vector3d m = truth * p + Eigen::Vector3d(0.003 * n(rng), 0.003 * n(rng), 0.01 * n(rng));
    if (i % 7 == 3) m = -8.0 * p;            // an outlier in the wrong direction
    if (i % 7 == 5) m = 40.0 * p;            // an outlier far too large
    est.add_pair(p, m);
  }
  CHECK(est.status().estimated);
  CHECK(est.status().inliers < est.status().pairs);
  CHECK(est.scale() == Approx(truth).epsilon(0.03));
  CHECK(est.status().accuracy > 0.5);
  CHECK(est.status().relative_std < 0.03);
  // Too-short displacements are ignored, non-finite refused.
  CHECK_FALSE(est.add_pair(Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0.02, 0, 0)));
  CHECK_FALSE(est.add_pair(Eigen::Vector3d(NAN, 0, 1), Eigen::Vector3d(1, 0, 0)));
  // A pair pointing the other way is no scale at all.
  CHECK_FALSE(est.add_pair(Eigen::Vector3d(0, 0, 0.3), Eigen::Vector3d(0, 0, -0.8)));
}

namespace {
// Pairs of a vertical manoeuvre (weighted as the estimator does: z x3) for a map of `metres_per_unit`.
void add_manoeuvre_pairs(estimation::ScaleEstimator& est, double metres_per_unit, int n, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d metric(0.02 * noise(rng) / 0.01, 0.0, 3.0 * (i % 2 == 0 ? 0.25 : -0.2));
    Eigen::Vector3d map = metric / metres_per_unit;
    map += Eigen::Vector3d(noise(rng), noise(rng), 1.5 * noise(rng)) / metres_per_unit;
    est.add_pair(map, metric + Eigen::Vector3d(noise(rng), noise(rng), 1.5 * noise(rng)));
  }
}
}  // namespace

TEST_CASE("estimation: the scale is found whatever the map's unit, from the third pair on") {
  // A monocular map's unit is its initial median depth: 6-10 m in the simulated lab. The first
  // implementation rejected every pair as an outlier against the initial scale (1) until five had
  // come, and its 5 cm minimum was in map units (0.5 m of real motion at 10 m/unit).
  for (const double metres_per_unit : {0.2, 1.0, 8.0, 40.0}) {
    std::mt19937 rng(5);
    estimation::ScaleEstimator est{estimation::ScaleSettings{}};
    add_manoeuvre_pairs(est, metres_per_unit, 2, rng);
    CHECK_FALSE(est.status().estimated);
    add_manoeuvre_pairs(est, metres_per_unit, 1, rng);
    INFO("map unit " << metres_per_unit << " m: scale " << est.scale());
    CHECK(est.status().estimated);
    CHECK(est.status().inliers == 3);
    CHECK(est.scale() == Approx(metres_per_unit).epsilon(0.03));
  }
}

TEST_CASE("estimation: the scale follows a map whose scale drifts") {
  // As a monocular map in the simulated lab does: 10 m/unit during the manoeuvre, 6 m/unit after the
  // map's first adjustments. Without forgetting, the estimate would stay near the mean.
  std::mt19937 rng(9);
  estimation::ScaleEstimator est{estimation::ScaleSettings{}};
  add_manoeuvre_pairs(est, 10.0, 8, rng);
  CHECK(est.scale() == Approx(10.0).epsilon(0.03));
  CHECK(est.scale_changes() == 0);
  // Two pairs of the changed map, refused by the gate but agreeing: the estimate starts again.
  add_manoeuvre_pairs(est, 6.0, 2, rng);
  INFO("scale " << est.scale() << ", outliers at arrival " << est.outliers_at_arrival());
  CHECK(est.scale_changes() == 1);
  CHECK(est.scale() == Approx(6.0).epsilon(0.06));  // from two pairs of ~3 % noise each
  CHECK(est.status().estimated);  // still known: SLAM stays fused
  add_manoeuvre_pairs(est, 6.0, 10, rng);
  CHECK(est.scale() == Approx(6.0).epsilon(0.05));  // ~10 pairs of 1.5 cm noise: sigma ~1.5 %
  CHECK(est.scale_changes() == 1);
}

TEST_CASE("estimation: one outlier does not restart the scale, nor two that disagree") {
  std::mt19937 rng(4);
  estimation::ScaleEstimator est{estimation::ScaleSettings{}};
  add_manoeuvre_pairs(est, 8.0, 8, rng);
  CHECK(est.add_pair(Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, 0.1 * 8.0 * 1.5)));
  CHECK(est.add_pair(Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, 0.1 * 8.0 * 0.6)));
  CHECK(est.outliers_at_arrival() == 2);
  CHECK(est.scale_changes() == 0);
  CHECK(est.scale() == Approx(8.0).epsilon(0.03));
}

TEST_CASE("estimation: a pair far off the scale is an outlier, a noisy one is not") {
  std::mt19937 rng(3);
  estimation::ScaleEstimator est{estimation::ScaleSettings{}};
  add_manoeuvre_pairs(est, 5.0, 6, rng);
  const int inliers = est.status().inliers;
  // 30 % too long (the metric side read a floor step as motion): refused by the chi2 gate.
  CHECK(est.add_pair(Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(0, 0, 0.15 * 5.0 * 1.3)));
  CHECK(est.status().inliers == inliers);
  CHECK(est.outliers_at_arrival() == 1);
  CHECK(est.scale() == Approx(5.0).epsilon(0.03));
  // 3 % off: within the noise, kept.
  CHECK(est.add_pair(Eigen::Vector3d(0, 0, 0.15), Eigen::Vector3d(0, 0, 0.15 * 5.0 * 1.03)));
  CHECK(est.status().inliers == inliers + 1);
}

TEST_CASE("estimation: map-to-world keeps the fixpoint when the scale changes") {
  const Eigen::Isometry3d T_map_cam = make_pose({0.3, -0.2, 0.5}, 0.4, 0.1, -0.2);
  const Eigen::Isometry3d T_world_cam = make_pose({1.0, 2.0, 1.2}, -1.0, 0.05, 0.02);
  estimation::MapToWorld m;
  m.initialize(T_map_cam, T_world_cam, 0.5);
  CHECK((m.T_world_cam(T_map_cam).matrix() - T_world_cam.matrix()).norm() < 1e-9);
  const Eigen::Isometry3d other = make_pose({1.3, 0.2, -0.5}, 0.2, 0, 0);
  const Eigen::Vector3d before = m.T_world_cam(other).translation();
  m.set_scale(1.5);
  // The fixpoint (the first camera) stays where it was; other points scale about it.
  CHECK((m.T_world_cam(T_map_cam).translation() - T_world_cam.translation()).norm() < 1e-9);
  const Eigen::Vector3d after = m.T_world_cam(other).translation();
  CHECK((after - T_world_cam.translation()).norm() ==
        Approx(3.0 * (before - T_world_cam.translation()).norm()).epsilon(1e-9));
}

TEST_CASE("estimation: a scale pair closes on enough motion, not after a fixed time") {
  estimation::ScalePairSampler sampler(1.0, 3.0, Eigen::Vector3d(1.0, 1.0, 3.0), 0.3);
  const auto run = [&](double vx, double vz, Seconds until, Seconds& t) {
    std::optional<estimation::ScalePair> first;
    for (; t < until && !first; t += 1.0 / 30.0) {
      estimation::ScaleSample s;
      s.t = t;
      s.metric = Eigen::Vector3d(vx * t, 0, 1.0 + vz * t);
      s.p_map = s.metric / 7.0;
      first = sampler.add(s);
    }
    return first;
  };
  Seconds t = 0;
  // Slow sideways drift, 5 cm/s: 30 cm take 6 s, longer than the 3 s an interval may last.
  CHECK_FALSE(run(0.05, 0.0, 10.0, t).has_value());
  // Climbing 6 cm/s: 10 cm of climb (0.3 weighted) after about 1.7 s, past the 1 s minimum.
  sampler.reset();
  t = 0;
  const auto pair = run(0.0, 0.06, 10.0, t);
  REQUIRE(pair.has_value());
  CHECK(pair->interval > 1.5);
  CHECK(pair->interval < 2.2);
  CHECK(pair->metric_displacement.z() == Approx(0.06 * pair->interval).epsilon(0.05));
  CHECK(pair->map_displacement.z() == Approx(pair->metric_displacement.z() / 7.0).epsilon(1e-9));
}

// A Tello's state comes every 0.1 s with jitter: its pairs must not all count as navdata gaps, and the
// AR.Drone's 0.1 s limit must still refuse a real gap.
TEST_CASE("estimation: a pair's navdata coverage is judged by the telemetry's rate (scale_max_navdata_gap_s)") {
  const auto first_pair = [](Seconds max_gap, Seconds navdata_gap) {
    estimation::ScalePairSampler sampler(1.0, 3.0, Eigen::Vector3d(1.0, 1.0, 3.0), 0.3, max_gap);
    std::optional<estimation::ScalePair> pair;
    for (Seconds t = 0; t < 5.0 && !pair; t += 1.0 / 30.0) {
      estimation::ScaleSample s;
      s.t = t;
      s.metric = Eigen::Vector3d(0, 0, 1.0 + 0.1 * t);
      s.p_map = s.metric / 7.0;
      s.navdata_gap = navdata_gap;
      pair = sampler.add(s);
    }
    REQUIRE(pair.has_value());
    return pair->coverage_ok;
  };
  CHECK_FALSE(first_pair(0.1, 0.104));  // a 10 Hz state a little late: over the AR.Drone's 1.5 periods
  CHECK(first_pair(0.15, 0.104));       // within a Tello's
  CHECK_FALSE(first_pair(0.15, 0.2));   // a lost state string is a gap either way
}
