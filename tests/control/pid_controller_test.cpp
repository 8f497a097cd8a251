#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "control/pid_controller.hpp"
#include "core/frames.hpp"

using namespace labo;
using namespace labo::control;

namespace {
fusion::PoseEstimate at(const Eigen::Vector3d& p, double yaw, const Eigen::Vector3d& v = Eigen::Vector3d::Zero()) {
  fusion::PoseEstimate e;
  e.valid = true;
  e.T_world_body = make_pose(p, yaw);
  e.velocity_world = v;
  return e;
}
}  // namespace

TEST_CASE("control: PID output is clipped to its limits") {
  control::PidAxis axis({2.0, 0.0, 0.0, 0.0, -0.25, 0.5});
  CHECK(axis.update(10.0, 0.0, 0.03) == Approx(0.5));
  CHECK(axis.update(-10.0, 0.0, 0.03) == Approx(-0.25));
  CHECK(axis.update(0.1, 0.0, 0.03) == Approx(0.2));
}

TEST_CASE("control: PID derivative acts on the measured rate, not on the error") {
  control::PidAxis axis({1.0, 0.0, 0.5, 0.0, -1, 1});
  // A target step gives no derivative kick: the output is the P term only.
  CHECK(axis.update(0.4, 0.0, 0.03) == Approx(0.4));
  // Moving towards the target at 0.4 m/s damps the command.
  CHECK(axis.update(0.4, 0.4, 0.03) == Approx(0.2));
}

TEST_CASE("control: PID integral does not wind up while saturated and is capped") {
  control::PidAxis axis({1.0, 0.1, 0.0, 2.0, -1, 1});
  for (int i = 0; i < 1000; ++i) axis.update(5.0, 0.0, 0.03);  // P alone saturates: no integration
  CHECK(axis.integral() == Approx(0.0));
  for (int i = 0; i < 2000; ++i) axis.update(0.5, 0.0, 0.03);  // unsaturated: integrates up to the cap
  CHECK(axis.integral() == Approx(2.0));
  CHECK(axis.update(0.5, 0.0, 0.03) == Approx(0.7));
}

TEST_CASE("control: PID integral unwinds faster against the error and stops at zero") {
  control::PidAxis axis({0.1, 1.0, 0.0, 10.0, -1, 1});
  for (int i = 0; i < 10; ++i) axis.update(0.05, 0.0, 0.1);
  const double before = axis.integral();
  REQUIRE(before == Approx(0.05));
  axis.update(-0.1, 0.0, 0.1);  // opposing: 2.5 * -0.1 * 0.1 = -0.025
  CHECK(axis.integral() == Approx(0.025));
  axis.update(-1.0, 0.0, 0.1);  // would cross zero: stops at zero
  CHECK(axis.integral() == 0.0);
}

TEST_CASE("control: a new target resets the integrals, a moving set point keeps them") {
  control::PoseControlGains g;
  g.z = {0.1, 1.0, 0.0, 5.0, -1, 1};
  control::PoseController c(g);
  c.set_target({{0, 0, 1.0}, 0});
  for (int i = 0; i < 20; ++i) c.update(at({0, 0, 0.5}, 0), 0.03);
  REQUIRE(c.axis_z().integral() > 0.1);
  c.set_target({{0, 0, 1.05}, 0}, /*keep_state=*/true);
  CHECK(c.axis_z().integral() > 0.1);
  c.set_target({{0, 0, 1.2}, 0});
  CHECK(c.axis_z().integral() == 0.0);
}

TEST_CASE("control: horizontal errors are rotated into the body frame") {
  control::PoseControlGains g;
  g.xy = {0.5, 0, 0, 0, -1, 1};
  g.max_tilt_command = 1.0;
  control::PoseController c(g);
  c.set_target({{1.0, 0, 1}, std::numbers::pi / 2});
  // Facing +y (yaw 90 deg), a target at +x world is on the drone's right: roll right, no pitch.
  MoveCommand m = c.update(at({0, 0, 1}, std::numbers::pi / 2), 0.03);
  CHECK(m.roll == Approx(0.5));
  CHECK(m.pitch == Approx(0.0).margin(1e-9));
  // Facing +x, the same target is straight ahead: pitch forward.
  c.set_target({{1.0, 0, 1}, 0});
  m = c.update(at({0, 0, 1}, 0), 0.03);
  CHECK(m.pitch == Approx(0.5));
  CHECK(m.roll == Approx(0.0).margin(1e-9));
  // Facing -x with velocity towards +x world: the damping is rotated too.
  g.xy.kd = 0.5;
  control::PoseController d(g);
  d.set_target({{0, 0, 1}, std::numbers::pi});
  m = d.update(at({0, 0, 1}, std::numbers::pi, {1.0, 0, 0}), 0.03);
  CHECK(m.pitch == Approx(0.5));  // moving backwards: push forward
}

TEST_CASE("control: the horizontal command is clipped as a vector, keeping its direction") {
  control::PoseControlGains g;
  g.xy = {1.0, 0, 0, 0, -1, 1};
  g.max_tilt_command = 0.3;
  control::PoseController c(g);
  c.set_target({{3.0, 4.0, 1}, 0});
  const MoveCommand m = c.update(at({0, 0, 1}, 0), 0.03);
  CHECK(std::hypot(m.pitch, m.roll) == Approx(0.3));
  CHECK(m.pitch / -m.roll == Approx(3.0 / 4.0));
}

TEST_CASE("control: yaw error is wrapped across +-180 degrees") {
  control::PoseControlGains g;
  g.yaw = {1.0, 0, 0, 0, -1, 1};
  control::PoseController c(g);
  c.set_target({{0, 0, 1}, -3.0});
  const MoveCommand m = c.update(at({0, 0, 1}, 3.0), 0.03);
  CHECK(m.yaw_rate == Approx(wrap_angle(-3.0 - 3.0)));
  CHECK(m.yaw_rate > 0);  // the short way round: counter-clockwise
}

TEST_CASE("control: a turning set point's yaw rate is fed forward, so the yaw does not lag it") {
  control::PoseControlGains g;  // yaw kp 2.0, yaw_rate_feedforward 0.57 command per rad/s
  control::PoseController c(g);
  control::PoseTarget target{{0, 0, 1}, 0.5};
  target.yaw_rate = 0.5;  // rad/s
  c.set_target(target);
  fusion::PoseEstimate turning = at({0, 0, 1}, 0.5);
  turning.yaw_rate = 0.5;
  // On the set point and turning with it: keep turning (before: 0, the drone stopped and fell behind).
  CHECK(c.update(turning, 0.03).yaw_rate == Approx(g.yaw_rate_feedforward * 0.5));
  // Clipped to the command range.
  target.yaw_rate = 5.0;
  c.set_target(target, true);
  CHECK(c.update(turning, 0.03).yaw_rate == Approx(1.0));
}
