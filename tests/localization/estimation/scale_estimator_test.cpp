#include <catch2/catch.hpp>
#include <random>

#include "core/frames.hpp"
#include "localization/estimation/scale_estimator.hpp"

using namespace labo;

TEST_CASE("estimation: ML scale reaches its two limits") {
  const double s_pp = 2.0, s_ii = 9.0, s_pi = 4.1;
  // Exact metric displacements: lambda = S_II / S_PI; exact map displacements: lambda = S_PI / S_PP.
  CHECK(ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 0.2, 1e-9) == Approx(s_ii / s_pi).epsilon(1e-6));
  CHECK(ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 1e-9, 0.2) == Approx(s_pi / s_pp).epsilon(1e-6));
  CHECK(ScaleEstimator::ml_scale(s_pp, s_ii, s_pi, 0.2, 0.2) > s_pi / s_pp);
}

TEST_CASE("estimation: scale estimator recovers the scale from noisy pairs with outliers") {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const double truth = 2.7;
  ScaleEstimator est(0.2, 0.01, 0.1, 1.0);
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
}

TEST_CASE("estimation: map-to-world keeps the fixpoint when the scale changes") {
  const Eigen::Isometry3d T_map_cam = make_pose({0.3, -0.2, 0.5}, 0.4, 0.1, -0.2);
  const Eigen::Isometry3d T_world_cam = make_pose({1.0, 2.0, 1.2}, -1.0, 0.05, 0.02);
  MapToWorld m;
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
