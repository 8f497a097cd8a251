// The link-cut envelope: commands that would carry the drone into a wall during the firmware's
// command hold are scaled down or become a hover; everything else passes untouched.
#include <catch2/catch.hpp>

#include "control/command_hold_envelope.hpp"

using namespace labo;
using namespace labo::control;

namespace {

// The default lab's room, the default model, 2 s of hold, 0.2 m clearance.
CommandHoldEnvelope lab_envelope() {
  return CommandHoldEnvelope({-1.5, -3.0, 0.0}, {6.5, 3.0, 3.0}, 0.2, 2.0, estimation::MotionModelConstants{});
}

HoldEnvelopeInputs at(double x, double vx, double yaw_rad = 3.14159265358979) {
  return {{x, 0.0, 1.6}, {vx, 0.0, 0.0}, yaw_rad};
}

}  // namespace

TEST_CASE("hold envelope: a slow or braking command in the open passes untouched") {
  const auto env = lab_envelope();
  const MoveCommand cruise{0.0, 0.3, 0.0, 0.0};
  const auto r = env.limit(cruise, at(3.0, -0.5));  // facing -x, 4.5 m from the wall
  CHECK_FALSE(r.limited());
  CHECK(r.move.pitch == 0.3);
  const auto braking = env.limit(MoveCommand{0.0, -0.5, 0.0, 0.0}, at(0.0, -1.0));
  CHECK_FALSE(braking.limited());
}

TEST_CASE("hold envelope: flying fast at a wall, the command is scaled so that a cut stops short of it") {
  const auto env = lab_envelope();
  // 1 m/s towards the x_min wall (at -1.5), 4.5 m from it, tilted on towards it.
  const MoveCommand forward{0.0, 0.3, 0.0, 0.0};
  const HoldEnvelopeInputs s = at(3.0, -1.0);
  CHECK(env.rest_point(forward, s).x() < -1.5);
  const auto r = env.limit(forward, s);
  REQUIRE(r.limited());
  CHECK_FALSE(r.hover);
  CHECK(env.rest_point(r.move, s).x() >= -1.3 - 1e-6);
  {
    CHECK(r.scale < 1.0);
    CHECK(r.move.pitch == Approx(0.3 * r.scale));
  }
}

TEST_CASE("hold envelope: too fast for any tilt, a command leading on becomes a hover, one braking stays") {
  const auto env = lab_envelope();
  const HoldEnvelopeInputs s = at(-0.8, -1.5);  // 0.7 m from the wall at 1.5 m/s
  const auto on = env.limit(MoveCommand{0.0, 0.3, 0.0, 0.0}, s);
  CHECK(on.hover);
  CHECK(on.move.pitch == 0.0);
  const auto brake = env.limit(MoveCommand{0.0, -1.0, 0.0, 0.0}, s);  // full tilt against the motion
  CHECK_FALSE(brake.hover);
  CHECK(brake.move.pitch == -1.0);
}

TEST_CASE("hold envelope: near a wall at rest, leading away passes and leading in is refused") {
  const auto env = lab_envelope();
  const HoldEnvelopeInputs s = at(-1.4, 0.0);  // inside the clearance band, still
  CHECK_FALSE(env.limit(MoveCommand{0.0, -0.3, 0.0, 0.0}, s).limited());  // backwards = +x: away
  CHECK(env.limit(MoveCommand{0.0, 0.3, 0.0, 0.0}, s).hover);
}

TEST_CASE("hold envelope: a climb held into the ceiling is scaled, a descent never") {
  const auto env = lab_envelope();
  HoldEnvelopeInputs s = at(2.0, 0.0);
  s.position_m.z() = 2.4;
  const auto climb = env.limit(MoveCommand{0.0, 0.0, 1.0, 0.0}, s);
  REQUIRE(climb.limited());
  CHECK(env.rest_point(climb.move, s).z() <= 2.8 + 1e-6);
  s.position_m.z() = 0.3;
  CHECK_FALSE(env.limit(MoveCommand{0.0, 0.0, -1.0, 0.0}, s).limited());
}
