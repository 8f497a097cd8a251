#include <catch2/catch.hpp>

#include "control/estimate_correction.hpp"

using namespace labo;

namespace {
fusion::PoseEstimate estimate(const Eigen::Vector3d& p, const Eigen::Vector3d& v, bool valid = true) {
  fusion::PoseEstimate e;
  e.valid = valid;
  e.T_world_body.translation() = p;
  e.velocity_world = v;
  return e;
}
}  // namespace

TEST_CASE("control: an estimate's correction is the displacement its velocity does not explain") {
  control::EstimateCorrection c;
  CHECK(c.update(estimate({0, 0, 1}, {0.5, 0, 0}), 0.0).isZero());  // the first call
  // Flying at 0.5 m/s along x for 0.1 s: all motion, no correction.
  CHECK(c.update(estimate({0.05, 0, 1}, {0.5, 0, 0}), 0.1).norm() < 1e-12);
  // Accelerating: the velocity's trapezoid explains the displacement.
  CHECK(c.update(estimate({0.11, 0, 1}, {0.7, 0, 0}), 0.2).norm() < 1e-12);
  // A fix moves the estimate 0.3 m back while it flies on at 0.7 m/s.
  const Eigen::Vector3d fix = c.update(estimate({0.11 + 0.07 - 0.3, 0, 1}, {0.7, 0, 0}), 0.3);
  CHECK(fix.x() == Approx(-0.3));
  CHECK(fix.tail<2>().norm() < 1e-12);
}

TEST_CASE("control: an estimate's correction is zero without a previous valid estimate or elapsed time") {
  control::EstimateCorrection c;
  c.update(estimate({0, 0, 1}, {0, 0, 0}), 0.0);
  CHECK(c.update(estimate({0.4, 0, 1}, {0, 0, 0}), 0.0).isZero());     // no time passed
  CHECK(c.update(estimate({0, 0, 0}, {0, 0, 0}, false), 0.1).isZero());  // invalid: forgotten
  CHECK(c.update(estimate({2.0, 1.0, 1}, {0, 0, 0}), 0.2).isZero());   // the first valid one again
  CHECK(c.update(estimate({2.0, 1.1, 1}, {0, 0, 0}), 0.3).y() == Approx(0.1));
}
