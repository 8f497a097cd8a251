// SimulatedLab as an EmulatedVehicle: seed determinism bit for bit whatever the caller's step
// pattern, the firmware's behaviour through the vehicle interface, both cameras rendered (the
// renderer's own tests are tests/drone/sim/render_*_test.cpp).
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/camera_config.hpp"
#include "core/frames.hpp"
#include "drone/sim/sim_setup.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::sim;

namespace {

SimulatedLab make_lab(std::uint64_t seed) {
  SimulatedLabSettings s;
  s.seed = seed;
  return SimulatedLab(test::shipped_lab(), s, std::make_unique<test::GreyRenderer>());
}

// A scripted flight; the vehicle is advanced every `granularity_s` between commands, as an emulator
// or a lockstep link would, and its telemetry recorded at 15 Hz. Commands and records are handled in
// time order.
std::vector<VehicleTelemetry> scripted_flight(SimulatedLab& v, Seconds granularity_s) {
  struct Command {
    Seconds t;
    int kind;  // 0 take-off, 1 move, 2 hover, 3 land
    MoveCommand move;
  };
  const std::vector<Command> script = {{0.5, 0, {}},           {6.013, 1, {0.1, 0.4, 0.0, 0.2}}, {7.5, 1, {-0.3, 0.0, 0.3, 0.0}},
                                       {8.77, 2, {}},          {10.0, 1, {0.0, -0.3, 0.0, -0.5}}, {11.2, 3, {}}};
  std::vector<VehicleTelemetry> out;
  std::size_t next = 0;
  int record = 0;
  for (Seconds t = 0; t < 20.0; t += granularity_s) {
    v.advance_to(t);
    for (;;) {
      const Seconds record_t = record / 15.0;
      const bool command_first = next < script.size() && script[next].t < record_t;
      const Seconds due = command_first ? script[next].t : record_t;
      if (due > t + granularity_s) break;
      if (command_first) {
        const Command& c = script[next++];
        if (c.kind == 0) v.takeoff(c.t);
        if (c.kind == 1) v.move(c.move, false, c.t);
        if (c.kind == 2) v.move({}, true, c.t);
        if (c.kind == 3) v.land(c.t);
      } else {
        v.advance_to(record_t);
        out.push_back(v.telemetry());
        ++record;
      }
    }
  }
  return out;
}

bool same_bits(const VehicleTelemetry& a, const VehicleTelemetry& b) {
  const double va[] = {a.nav.t, a.nav.roll_rad, a.nav.pitch_rad, a.nav.yaw_rad, a.nav.altitude_m, a.nav.vx_mps,
                       a.nav.vy_mps, a.nav.vz_mps, a.nav.battery_percent, a.accel_body_mps2.z(), a.gyro_body_radps.x(), a.pressure_pa};
  const double vb[] = {b.nav.t, b.nav.roll_rad, b.nav.pitch_rad, b.nav.yaw_rad, b.nav.altitude_m, b.nav.vx_mps,
                       b.nav.vy_mps, b.nav.vz_mps, b.nav.battery_percent, b.accel_body_mps2.z(), b.gyro_body_radps.x(), b.pressure_pa};
  return std::memcmp(va, vb, sizeof va) == 0 && a.nav.control_state == b.nav.control_state;
}

}  // namespace

TEST_CASE("sim lab: the same seed gives the same flight bit for bit, whatever the caller's step pattern", "[sim][determinism]") {
  auto a = make_lab(42), b = make_lab(42), c = make_lab(43);
  const auto ta = scripted_flight(a, 0.001), tb = scripted_flight(b, 0.037), tc = scripted_flight(c, 0.001);
  REQUIRE(ta.size() == tb.size());
  bool same = true, differ = false;
  for (std::size_t i = 0; i < ta.size(); ++i) {
    same = same && same_bits(ta[i], tb[i]);
    differ = differ || !same_bits(ta[i], tc[i]);
  }
  CHECK(same);
  CHECK(differ);
  const Eigen::Isometry3d pa = a.truth().T_world_body(), pb = b.truth().T_world_body();
  CHECK(std::memcmp(pa.data(), pb.data(), sizeof(double) * 16) == 0);
  // The flight happened: took off, moved, landed back on the floor or the platform.
  bool flew = false;
  for (const auto& t : ta) flew = flew || (t.nav.control_state == 3 && t.nav.altitude_m > 0.8);
  CHECK(flew);
  CHECK(ta.back().nav.control_state == 2);
}

TEST_CASE("sim lab: telemetry reports the firmware's states, battery and the crash", "[sim]") {
  auto v = make_lab(1);
  v.advance_to(0.2);
  auto t = v.telemetry();
  CHECK(t.nav.control_state == 2);
  CHECK_FALSE(t.flying);
  CHECK(t.nav.altitude_m == 0.0);
  CHECK(t.accel_body_mps2.z() == Approx(9.81).margin(0.2));  // 1 g up at rest
  v.takeoff(0.3);
  v.advance_to(1.0);
  CHECK(v.telemetry().nav.control_state == 6);
  CHECK(v.telemetry().flying);
  v.advance_to(8.0);
  t = v.telemetry();
  CHECK(t.nav.control_state == 4);
  CHECK(t.nav.altitude_m == Approx(1.0).margin(0.1));
  CHECK(t.nav.battery_percent < 95.0);
  for (Seconds s = 8.0; s < 14.0; s += 0.03) v.move({0.0, -1.0, 0.0, 0.0}, false, s);  // into the wall behind
  v.advance_to(15.0);
  t = v.telemetry();
  CHECK(t.emergency);
  CHECK(t.motors_cut);
  CHECK_FALSE(t.flying);
  CHECK(v.truth().crash_reason == "wall_xmin");
}

TEST_CASE("sim lab: both cameras render the lab at their configured size", "[sim][render]") {
  auto v = make_simulated_lab(test::shipped_lab(), test::stock_cameras(), SimulatedLabSettings{});
  cv::Mat front, bottom;
  v->render(CameraId::Front, front);
  v->render(CameraId::Bottom, bottom);
  CHECK(front.size() == cv::Size(640, 360));
  CHECK(bottom.size() == cv::Size(640, 360));
  cv::Scalar mean, stddev;
  cv::meanStdDev(front, mean, stddev);
  CHECK(stddev[0] > 10);  // not a flat picture
  // From 1 m above the platform the bottom camera sees the landing pattern: black and white.
  v->takeoff(0.1);
  v->advance_to(8.0);
  v->render(CameraId::Bottom, bottom);
  cv::Mat grey;
  cv::cvtColor(bottom, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat centre = grey(cv::Rect(270, 130, 100, 100));
  double lo = 0, hi = 0;
  cv::minMaxLoc(centre, &lo, &hi);
  CHECK(lo < 60);
  CHECK(hi > 190);
}
