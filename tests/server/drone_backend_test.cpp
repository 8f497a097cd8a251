#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <thread>
#include <set>

#include "drone/replay/recording.hpp"
#include "drone/tello/tello_emulator.hpp"
#include "server/runtime/drone_backend.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::replay;
using namespace labo::tello;
using namespace labo::server;
using labo::test::ScratchDir;

namespace {

// Polls the flight's telemetry every 50 ms until `done` says so, for at most `timeout_s`.
template <typename Done>
bool telemetry_until(FlightService& flight, Done done, double timeout_s) {
  for (int i = 0; i < timeout_s * 20; ++i) {
    if (done(flight.telemetry())) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

}  // namespace

TEST_CASE("server: the flight software knows the instruments of the configured lab") {
  const ScratchDir scratch("backend_lab");
  const auto file = scratch / "flight.ldrec";
  {
    RecordingWriter w(file);
    w.note(0.0, "empty flight");
  }
  const AppConfig config = load_app_config(default_config_path());
  DroneSpec spec;
  spec.kind = DroneSpec::Kind::Replay;
  spec.file = file.string();
  const auto backend = make_drone_backend(spec, config, Logger("test", LogLevel::Off));
  std::set<std::string> ids;
  for (const auto& i : backend->flight().instruments()) ids.insert(i.id);
  CHECK(ids == std::set<std::string>{"oscilloscope", "signal_generator", "power_supply"});
  MissionCommand unknown;
  unknown.kind = MissionCommandKind::Inspect;
  unknown.instrument = "multimeter";
  const CommandVerdict v = backend->flight().request(unknown);
  CHECK_FALSE(v.accepted);
  CHECK_THAT(v.reason, Catch::Contains("oscilloscope"));
}

TEST_CASE("server: on the simulated lab the estimate follows the lab's truth through a take-off") {
  // The served stack over the real driver and the emulator, on the wall clock: the runtime's clock
  // has run for seconds (the teacher's face, the link) before navdata arrives. A filter anchored at
  // time 0 once rejected all of it and kept the drone at the base while it climbed (seen on the page
  // once the truth was drawn).
  const AppConfig config = load_app_config(default_config_path());
  const auto backend = make_drone_backend(DroneSpec{}, config, Logger("test", LogLevel::Off));
  FlightService& flight = backend->flight();
  const auto wait_for = [&](auto done, double timeout_s) { return telemetry_until(flight, done, timeout_s); };
  REQUIRE(wait_for([](const FlightTelemetry& t) { return t.ground_truth && t.link_state == "connected" && t.battery_percent > 0; }, 20));
  const FlightTelemetry landed = flight.telemetry();
  // Landed on the charging platform at the base (the lab's origin, its top 0.10 m above the floor).
  CHECK(std::hypot(landed.ground_truth->x_m, landed.ground_truth->y_m) < 0.05);
  CHECK(landed.ground_truth->z_m == Approx(0.10).margin(0.05));

  MissionCommand takeoff;
  takeoff.kind = MissionCommandKind::Takeoff;
  const CommandVerdict verdict = flight.request(takeoff);
  INFO(verdict.reason);
  REQUIRE(verdict.accepted);
  // The firmware climbs to about 1 m above the platform; wait until the truth is there and settled.
  REQUIRE(wait_for([](const FlightTelemetry& t) { return t.ground_truth && t.ground_truth->z_m > 1.0; }, 20));
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const FlightTelemetry up = flight.telemetry();
  REQUIRE(up.ground_truth);
  INFO("estimate z " << up.pose.z_m << " m, truth z " << up.ground_truth->z_m << " m");
  CHECK(std::abs(up.pose.z_m - up.ground_truth->z_m) < 0.15);
  CHECK(std::hypot(up.pose.x_m - up.ground_truth->x_m, up.pose.y_m - up.ground_truth->y_m) < 0.3);
  flight.land_and_stop(5);
}

TEST_CASE("server: --drone names the AR.Drone or the Tello, with an optional IP address") {
  CHECK(parse_drone_spec("sim").kind == DroneSpec::Kind::Sim);
  const DroneSpec tello = parse_drone_spec("tello");
  CHECK(tello.kind == DroneSpec::Kind::Tello);
  CHECK(tello.host == "192.168.10.1");  // the Tello's own access point
  CHECK(parse_drone_spec("tello:127.0.0.1").host == "127.0.0.1");
  CHECK(parse_drone_spec("ardrone").host == "192.168.1.1");
  CHECK(describe(parse_drone_spec("tello:10.0.0.7")) == "Tello (SDK 2.0) at 10.0.0.7");
  CHECK_THROWS_WITH(parse_drone_spec("tello:nowhere"), Catch::Contains("tello:HOST"));
  CHECK_THROWS_WITH(parse_drone_spec("bebop"), Catch::Contains("tello[:HOST]"));
}

TEST_CASE("server: a Tello backend flies the flight software through the Tello link") {
  // The emulated Tello on loopback; the link's state and video ports are free ones found here
  // (a Tello sends to fixed ports of its client, which the emulator must be told).
  auto free_port = [] { return ardrone2::Socket::udp(0, "127.0.0.1").local_port(); };
  test::TinyVehicle vehicle;
  TelloEmulatorSettings es;
  es.command_port = 0;
  es.client_state_port = free_port();
  es.client_video_port = free_port();
  es.video_width = 480;
  es.video_height = 360;
  TelloEmulator emulator(vehicle, es, Logger("test", LogLevel::Off));
  emulator.start();
  AppConfig config = load_app_config(default_config_path());
  config.tello.link.command_port = emulator.command_port();
  config.tello.link.state_port = es.client_state_port;
  config.tello.link.video_port = es.client_video_port;
  const auto backend = make_drone_backend(parse_drone_spec("tello:127.0.0.1"), config, Logger("test", LogLevel::Off));
  FlightService& flight = backend->flight();
  const auto wait_for = [&](auto done, double timeout_s) { return telemetry_until(flight, done, timeout_s); };
  REQUIRE(wait_for([](const FlightTelemetry& t) { return t.link_state == "connected" && t.battery_percent == 80; }, 10));
  MissionCommand takeoff;
  takeoff.kind = MissionCommandKind::Takeoff;
  const CommandVerdict verdict = flight.request(takeoff);
  INFO(verdict.reason);
  REQUIRE(verdict.accepted);
  REQUIRE(wait_for([&](const FlightTelemetry&) { return vehicle.snapshot().flying && vehicle.snapshot().z_m > 0.7; }, 10));
  flight.land_and_stop(5);
  CHECK(wait_for([&](const FlightTelemetry&) { return !vehicle.snapshot().flying; }, 5));
}
