// The SDK's distance moves: their arguments' ranges (refused with the reason), and TelloFirmware
// flying them over the simulated lab's vehicle, answered "ok" once done.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "drone/ardrone2/link_counters.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "drone/tello/tello_firmware.hpp"
#include "drone/tello/tello_moves.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::sim;
using namespace labo::tello;

namespace {

std::string refusal(const char* word, const char* args) {
  const MoveParse p = parse_distance_move(word, args, 50);
  REQUIRE(p.is_move);
  return p.plan ? "" : p.error;
}

// The firmware over the simulated lab, driven in 10 ms steps as the lockstep link drives it.
struct Drone {
  ardrone2::LinkCounters counters{Logger("test", LogLevel::Off)};
  TelloFirmware firmware{TelloFirmwareSettings{}, counters};
  SimulatedLab lab{test::shipped_lab(), SimulatedLabSettings{}, std::make_unique<test::GreyRenderer>()};
  Seconds t = 0;

  // Sends a command; returns its reply (waiting up to `wait_s` for a motion's).
  std::string send(const std::string& text, Seconds wait_s = 30.0) {
    t += 0.01;
    std::optional<TelloFirmware::Reply> reply = firmware.command(text, lab, t);
    for (const Seconds until = t + wait_s; !reply && t < until;) {
      t += 0.01;
      reply = firmware.advance(lab, t);
    }
    return reply ? reply->text : "(none)";
  }
  void wait(Seconds s) {
    for (const Seconds until = t + s; t < until;) {
      t += 0.01;
      firmware.advance(lab, t);
    }
  }
  Eigen::Vector3d position() const { return lab.truth().position_m; }
  double yaw() const { return lab.truth().yaw_rad; }
};

double wrapped(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

}  // namespace

TEST_CASE("tello moves: arguments out of the SDK's ranges are refused with the reason", "[tello]") {
  CHECK(refusal("forward", "19") == "distance out of range [20, 500]");
  CHECK(refusal("up", "501") == "distance out of range [20, 500]");
  CHECK(refusal("left", "fifty") == "expected one integer distance in cm");
  CHECK(refusal("back", "50 50") == "expected one integer distance in cm");
  CHECK(refusal("cw", "0") == "angle out of range [1, 360]");
  CHECK(refusal("ccw", "361") == "angle out of range [1, 360]");
  CHECK(refusal("go", "10 -10 20 50") == "x, y and z all within [-20, 20]");
  CHECK(refusal("go", "100 0 0 9") == "speed out of range [10, 100]");
  CHECK(refusal("go", "501 0 0 50") == "x, y, z out of range [-500, 500]");
  CHECK(refusal("go", "100 0 0") == "expected x y z speed, integers");
  CHECK(refusal("curve", "100 0 0 200 0 0 20") == "the start and the two points lie on a line: no arc");
  CHECK(refusal("curve", "50 50 0 100 0 0 61") == "speed out of range [10, 60]");
  CHECK(refusal("curve", "20 25 0 30 0 0 20") == "arc radius out of range [0.5, 10] m");
  CHECK(refusal("flip", "x") == "expected l, r, f or b");
  CHECK_FALSE(parse_distance_move("jump", "1 2 3 4 5 m1 m2", 50).is_move);
  // Planned in the drone's frame at the start: x forward, y left, z up; speed from "speed".
  const MoveParse right = parse_distance_move("right", "40", 30);
  REQUIRE(right.plan);
  CHECK(right.plan->waypoints.back().isApprox(Eigen::Vector3d(0, -0.4, 0)));
  CHECK(right.plan->speed_mps == Approx(0.3));
  const MoveParse cw = parse_distance_move("cw", "90", 30);
  REQUIRE(cw.plan);
  CHECK(cw.plan->turn_rad == Approx(-std::numbers::pi / 2));
  // A half circle of radius 0.5 m: through (0.5, 0.5, 0) to (1, 0, 0).
  const MoveParse arc = parse_distance_move("curve", "50 50 0 100 0 0 20", 50);
  REQUIRE(arc.plan);
  CHECK(arc.plan->waypoints.back().isApprox(Eigen::Vector3d(1, 0, 0), 1e-9));
  CHECK(arc.plan->speed_mps == Approx(0.2));
  bool passes_p1 = false;
  for (const auto& p : arc.plan->waypoints) passes_p1 = passes_p1 || (p - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 0.06;
  CHECK(passes_p1);
}

TEST_CASE("tello moves: the emulated Tello flies them and answers ok once done", "[tello]") {
  Drone d;
  REQUIRE(d.send("command") == "ok");
  CHECK(d.send("forward 50") == "error not flying");
  REQUIRE(d.send("takeoff") == "ok");
  d.wait(1.0);
  REQUIRE(d.send("speed 50") == "ok");

  Eigen::Vector3d from = d.position();
  double yaw0 = d.yaw();
  const Seconds sent = d.t;
  REQUIRE(d.send("forward 100") == "ok");
  CHECK(d.t - sent > 1.5);  // answered after the move, not when received
  Eigen::Vector3d moved = d.position() - from;
  CHECK(moved.x() * std::cos(yaw0) + moved.y() * std::sin(yaw0) == Approx(1.0).margin(0.1));
  CHECK(std::abs(-moved.x() * std::sin(yaw0) + moved.y() * std::cos(yaw0)) < 0.1);

  yaw0 = d.yaw();
  REQUIRE(d.send("cw 90") == "ok");
  CHECK(wrapped(d.yaw() - yaw0) == Approx(-std::numbers::pi / 2).margin(0.06));  // clockwise: yaw falls

  from = d.position();
  REQUIRE(d.send("up 40") == "ok");
  CHECK(d.position().z() - from.z() == Approx(0.4).margin(0.08));

  // "go": in the frame at its start (now turned 90 deg clockwise: its left is the world's old forward).
  from = d.position();
  yaw0 = d.yaw();
  REQUIRE(d.send("go 0 60 0 40") == "ok");
  moved = d.position() - from;
  CHECK(-moved.x() * std::sin(yaw0) + moved.y() * std::cos(yaw0) == Approx(0.6).margin(0.1));

  from = d.position();
  yaw0 = d.yaw();
  REQUIRE(d.send("curve 50 50 0 100 0 0 30") == "ok");
  moved = d.position() - from;
  CHECK(moved.x() * std::cos(yaw0) + moved.y() * std::sin(yaw0) == Approx(1.0).margin(0.15));

  REQUIRE(d.send("flip l") == "ok");
  CHECK(d.send("back 19") == "error distance out of range [20, 500]");

  // While a move runs: other commands are refused, rc is ignored, stop ends it (its "error" first).
  d.t += 0.01;
  CHECK_FALSE(d.firmware.command("back 200", d.lab, d.t).has_value());
  d.wait(0.5);
  CHECK(d.send("speed?", 0.0) == "error");
  d.t += 0.01;
  CHECK_FALSE(d.firmware.command("rc 0 0 0 0", d.lab, d.t).has_value());
  d.t += 0.01;
  const auto stopped = d.firmware.command("stop", d.lab, d.t);
  REQUIRE(stopped);
  CHECK(stopped->text == "error");
  d.t += 0.05;
  const auto after = d.firmware.advance(d.lab, d.t);
  REQUIRE(after);
  CHECK(after->text == "ok");
  CHECK(d.counters.get("moves") == 6);
  CHECK(d.counters.get("flips") == 1);
  CHECK(d.counters.get("moves_stopped") == 1);
  CHECK(d.counters.get("rc_ignored_during_move") == 1);
  CHECK(d.counters.get("move_refused") == 2);
  CHECK(d.counters.get("moves_timed_out") == 0);
  REQUIRE(d.send("land") == "ok");
}
