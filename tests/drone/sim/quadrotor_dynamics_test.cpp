// QuadrotorDynamics against the model it implements: first-order lags with the fitted rates, the
// firmware's limits, take-off, hover, landing, altitude window and crashes.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "core/frames.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;

namespace {

QuadrotorDynamics make(const QuadrotorParams& p = {}, const Eigen::Isometry3d& start = test::shipped_lab().T_world_base) {
  return QuadrotorDynamics(p, CollisionModel(test::shipped_lab(), p.hull), start);
}

void run(QuadrotorDynamics& d, Seconds duration) {
  const int n = static_cast<int>(std::lround(duration / d.params().step_s));
  for (int i = 0; i < n; ++i) d.step();
}

// Takes off and waits for the firmware's hover.
void take_off(QuadrotorDynamics& d) {
  d.takeoff();
  for (int i = 0; i < 4000 && d.state().phase != FirmwarePhase::Hovering; ++i) d.step();
  REQUIRE(d.state().phase == FirmwarePhase::Hovering);
}

// Keeps sending the same PCMD every 30 ms, like the driver.
void fly(QuadrotorDynamics& d, const MoveCommand& c, Seconds duration) {
  for (Seconds t = 0; t < duration; t += 0.03) {
    d.move(c, false);
    run(d, 0.03);
  }
}

}  // namespace

TEST_CASE("sim dynamics: take-off climbs to about 1 m above the platform and hovers, landing touches down on it", "[sim][dynamics]") {
  auto d = make();
  CHECK(d.state().position_m.z() == Approx(0.10));  // on the platform top
  d.takeoff();
  run(d, 0.3);
  CHECK(d.state().phase == FirmwarePhase::TakingOff);
  CHECK(d.state().position_m.z() == Approx(0.10));  // spinning up
  take_off(d);
  CHECK(d.state().t < 8.0);
  CHECK(d.state().position_m.z() - 0.10 == Approx(1.0).margin(0.06));
  CHECK(control_state(d.state().phase) == 4);
  run(d, 5.0);  // the firmware holds the height and the position
  CHECK(d.state().position_m.z() - 0.10 == Approx(1.0).margin(0.06));
  CHECK(d.state().position_m.head<2>().norm() < 0.05);
  d.land();
  CHECK(control_state(d.state().phase) == 8);
  for (int i = 0; i < 4000 && d.state().phase != FirmwarePhase::Landed; ++i) d.step();
  CHECK(d.state().phase == FirmwarePhase::Landed);
  CHECK(d.state().position_m.z() == Approx(0.10));
  CHECK(d.state().velocity_mps.norm() == 0.0);
}

TEST_CASE("sim dynamics: roll and pitch follow the command with the fitted first-order lag up to euler_angle_max", "[sim][dynamics]") {
  QuadrotorParams p;
  auto d = make(p);
  take_off(d);
  const double tau = 1.0 / p.attitude_rate_per_s;
  const double target = 0.5 * p.tilt_max_rad;
  d.move({0.0, 0.5, 0.0, 0.0}, false);
  run(d, tau);
  CHECK(d.state().pitch_rad / target == Approx(1.0 - std::exp(-1.0)).margin(0.02));  // 63% after one time constant
  fly(d, {0.0, 0.5, 0.0, 0.0}, 1.0);
  CHECK(d.state().pitch_rad == Approx(target).margin(0.002));
  CHECK(d.state().velocity_mps.x() > 0.5);  // nose down flies forward

  fly(d, {-3.0, 1.0, 0.0, 0.0}, 1.2);  // beyond [-1, 1]: clipped
  CHECK(d.state().pitch_rad == Approx(p.tilt_max_rad).margin(0.002));
  CHECK(d.state().roll_rad == Approx(-p.tilt_max_rad).margin(0.002));
  CHECK(d.state().velocity_mps.y() > 0.2);  // roll < 0 (left side down) flies left, +y
}

TEST_CASE("sim dynamics: horizontal acceleration is g·tan(tilt) against the fitted linear drag", "[sim][dynamics]") {
  QuadrotorParams p;
  auto d = make(p);
  take_off(d);
  fly(d, {0.0, 0.6, 0.0, 0.0}, 1.0);  // the tilt has settled
  const auto& s = d.state();
  const double expected = p.gravity_mps2 * std::tan(s.pitch_rad) - p.drag_per_s * s.velocity_mps.x();
  CHECK(s.acceleration_mps2.x() == Approx(expected).margin(0.02));
  // Terminal speed of the fitted model: g·tan(θ)/drag.
  QuadrotorParams open = p;
  open.hull.radius_m = 0.01;
  auto far = make(open, make_pose({-1.0, -2.5, 0.0}, 0.0));
  take_off(far);
  fly(far, {0.0, 0.3, 0.0, 0.0}, 4.5);
  const double terminal = p.gravity_mps2 * std::tan(0.3 * p.tilt_max_rad) / p.drag_per_s;
  CHECK(far.state().velocity_mps.x() == Approx(terminal * (1 - std::exp(-p.drag_per_s * 4.2))).epsilon(0.06));
}

TEST_CASE("sim dynamics: yaw rate up to 100 deg/s and vertical speed up to 0.7 m/s, with their lags", "[sim][dynamics]") {
  QuadrotorParams p;
  auto d = make(p);
  take_off(d);
  fly(d, {0.0, 0.0, 0.0, 1.0}, 0.3);
  CHECK(d.state().yaw_rate_radps == Approx(p.yaw_rate_max_radps).epsilon(0.01));
  CHECK(p.yaw_rate_max_radps * 180 / std::numbers::pi == Approx(100).margin(0.01));
  fly(d, {0.0, 0.0, 0.0, -0.5}, 0.3);
  CHECK(d.state().yaw_rate_radps == Approx(-0.5 * p.yaw_rate_max_radps).epsilon(0.01));

  auto v = make(p);
  take_off(v);
  const double tau = 1.0 / p.vertical_response_per_s;
  const double vz0 = v.state().velocity_mps.z();
  v.move({0.0, 0.0, 1.0, 0.0}, false);
  run(v, tau);
  CHECK((v.state().velocity_mps.z() - vz0) / (p.vz_max_mps - vz0) == Approx(1.0 - std::exp(-1.0)).margin(0.02));
  v.move({0.0, 0.0, 1.0, 0.0}, false);
  run(v, 1.0);
  const double expected = p.vz_max_mps + (vz0 - p.vz_max_mps) * std::exp(-p.vertical_response_per_s * (tau + 1.0));
  CHECK(v.state().velocity_mps.z() == Approx(expected).margin(0.003));
  CHECK(v.state().velocity_mps.z() < p.vz_max_mps);
}

TEST_CASE("sim dynamics: the firmware hovers on PCMD flag 0 and after 2 s without a command", "[sim][dynamics]") {
  auto d = make();
  take_off(d);
  fly(d, {0.0, 0.8, 0.0, 0.0}, 1.0);
  CHECK(d.state().phase == FirmwarePhase::Flying);
  const double speed = d.state().velocity_mps.norm();
  CHECK(speed > 0.8);
  d.move({0.0, 0.8, 0.0, 0.0}, true);  // flag 0: the values are ignored
  run(d, 3.0);
  CHECK(d.state().phase == FirmwarePhase::Hovering);
  CHECK(d.state().velocity_mps.head<2>().norm() < 0.05);

  // A last command, then silence: flying for 2 s, then the firmware's hover brakes.
  d.move({0.0, 0.5, 0.0, 0.0}, false);
  run(d, 1.9);
  CHECK(d.state().phase == FirmwarePhase::Flying);
  CHECK(d.state().velocity_mps.x() > 0.5);
  run(d, 0.2);
  CHECK(d.state().phase == FirmwarePhase::Hovering);
  run(d, 2.5);
  CHECK(d.state().velocity_mps.head<2>().norm() < 0.05);
}

TEST_CASE("sim dynamics: the altitude window is measured above the surface below", "[sim][dynamics]") {
  QuadrotorParams p;
  p.altitude_max_m = 2.0;
  auto d = make(p);
  take_off(d);
  fly(d, {0.0, 0.0, 1.0, 0.0}, 14.0);
  CHECK(d.state().position_m.z() == Approx(0.10 + 2.0).margin(0.05));  // over the platform
  CHECK(d.state().phase == FirmwarePhase::Flying);
  fly(d, {0.0, 0.0, -1.0, 0.0}, 14.0);
  CHECK(d.state().position_m.z() == Approx(0.10 + p.altitude_min_m).margin(0.05));  // does not land
  CHECK(d.state().phase == FirmwarePhase::Flying);
}

TEST_CASE("sim dynamics: hitting a wall or a bench is a crash, the drone falls", "[sim][dynamics]") {
  auto d = make();
  take_off(d);
  fly(d, {0.0, -1.0, 0.0, 0.0}, 6.0);  // backwards, towards the wall at x = -1.5
  CHECK(d.state().phase == FirmwarePhase::Emergency);
  CHECK(d.state().crash_reason == "wall_xmin");
  CHECK(d.state().crashes == 1);
  CHECK(d.state().position_m.x() < -1.5 + 0.26 + 0.05);
  run(d, 1.0);
  CHECK(d.state().position_m.z() == Approx(0.0));  // on the floor
  CHECK_FALSE(d.state().airborne());
  d.takeoff();  // motors cut: no take-off until the emergency is cleared
  run(d, 0.5);
  CHECK(d.state().phase == FirmwarePhase::Emergency);
  d.emergency();
  CHECK(d.state().phase == FirmwarePhase::Landed);

  // Low over the floor towards the north bench (top 0.9 m): its side.
  auto b = make({}, make_pose({3.0, 1.0, 0.0}, 0.0));
  take_off(b);
  fly(b, {0.0, 0.0, -1.0, 0.0}, 3.0);
  REQUIRE(b.state().position_m.z() < 0.6);
  fly(b, {-1.0, 0.0, 0.0, 0.0}, 4.0);
  CHECK(b.state().crash_reason == "bench_north");
}

TEST_CASE("sim dynamics: an emergency cuts the motors in flight", "[sim][dynamics]") {
  auto d = make();
  take_off(d);
  d.emergency();
  CHECK(d.state().phase == FirmwarePhase::Emergency);
  CHECK(d.state().crash_reason.empty());
  run(d, 1.0);
  CHECK(d.state().position_m.z() == Approx(0.10));  // fell back onto the platform
}

TEST_CASE("sim dynamics: the battery drains faster in flight, empty, the firmware lands", "[sim][dynamics]") {
  QuadrotorParams p;
  p.battery_start_percent = 1.0;
  auto d = make(p);
  run(d, 10.0);
  CHECK(d.state().battery_percent == Approx(1.0 - 10 * p.battery_idle_drain_percent_per_s));
  take_off(d);
  fly(d, {}, 10.0);
  CHECK(d.state().battery_percent == 0.0);
  CHECK((d.state().phase == FirmwarePhase::Landing || d.state().phase == FirmwarePhase::Landed));
}

TEST_CASE("sim dynamics: a push and a wind move the hovering drone, the firmware brings it back to rest", "[sim][dynamics]") {
  auto d = make();
  take_off(d);
  d.push({0.0, 1.0, 0.0}, 0.5);
  run(d, 0.1);
  CHECK(d.state().velocity_mps.y() > 0.7);
  CHECK(d.state().yaw_rate_radps > 0.0);
  run(d, 4.0);
  CHECK(d.state().velocity_mps.norm() < 0.05);
  CHECK(d.state().position_m.y() > 0.2);  // a hover brakes, it does not return
  d.set_wind({0.5, 0.0, 0.0});
  run(d, 5.0);
  CHECK(d.state().velocity_mps.x() == Approx(0.5 * 0.58 / (0.58 + 2.0)).margin(0.02));  // P-only brake: a small drift
}
