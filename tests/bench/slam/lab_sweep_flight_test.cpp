#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "bench/slam/lab_flight.hpp"
#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"

using namespace labo;

namespace {
// The body's position and yaw from a front-camera pose.
Eigen::Isometry3d body_of(const Eigen::Isometry3d& T_world_cam) { return T_world_cam * T_body_cam_front().inverse(); }
double yaw_of(const Eigen::Isometry3d& T_world_body) { return std::atan2(T_world_body.linear()(1, 0), T_world_body.linear()(0, 0)); }
}  // namespace

TEST_CASE("bench slam: the lab sweep turns the camera round at face height, in place or out from a circle") {
  const lab::LabDescription lab = lab::load_lab_description(lab::default_lab_path());
  const double rate = 0.4;
  const double orbit_m = GENERATE(0.0, 0.35);
  const bench::Flight f = bench::lab_sweep_flight(lab, rate, 2, orbit_m);
  REQUIRE_FALSE(f.frames.empty());
  const Eigen::Vector3d start = body_of(f.frames.front().T_world_cam).translation();
  // Two full turns at 0.4 rad/s after the climb and the 8-s scale manoeuvre.
  double turned = 0, highest = 0, farthest = 0;
  for (std::size_t i = 1; i < f.frames.size(); ++i) {
    const Eigen::Isometry3d a = body_of(f.frames[i - 1].T_world_cam), b = body_of(f.frames[i].T_world_cam);
    const double step = std::remainder(yaw_of(b) - yaw_of(a), 2 * std::numbers::pi);
    CHECK(std::abs(step) <= rate / 30.0 + 1e-9);  // never faster than the sweep's rate
    turned += step;
    highest = std::max(highest, b.translation().z());
    farthest = std::max(farthest, (b.translation() - start).head<2>().norm());
  }
  CHECK(turned == Approx(4 * std::numbers::pi).margin(1e-6));
  CHECK(highest == Approx(1.6 + 0.4).margin(0.01));  // face height, and the manoeuvre's 0.4 m up
  const Eigen::Vector3d end = body_of(f.frames.back().T_world_cam).translation();
  CHECK(end.z() == Approx(1.6).margin(0.01));
  CHECK((end - start).head<2>().norm() == Approx(orbit_m).margin(0.01));
  CHECK(farthest == Approx(orbit_m).margin(0.01));
}
