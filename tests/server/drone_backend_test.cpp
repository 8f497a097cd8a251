#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <thread>
#include <set>

#include "drone/replay/recording.hpp"
#include "server/runtime/drone_backend.hpp"

using namespace labo;

TEST_CASE("server: the flight software knows the instruments of the configured lab") {
  const auto file = std::filesystem::temp_directory_path() / "labo_backend_lab_test.ldrec";
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
  std::filesystem::remove(file);
}

TEST_CASE("server: on the simulated lab the telemetry carries the lab's ground truth beside the estimate") {
  const AppConfig config = load_app_config(default_config_path());
  const auto backend = make_drone_backend(DroneSpec{}, config, Logger("test", LogLevel::Off));
  // The runtime ticks at the control rate as soon as it starts; give it up to 10 s on a loaded machine.
  std::optional<PoseXyzYaw> truth;
  for (int i = 0; i < 200 && !truth; ++i) {
    truth = backend->flight().telemetry().ground_truth;
    if (!truth) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  REQUIRE(truth);
  // Landed on the charging platform at the base (the lab's origin, its top 0.10 m above the floor).
  CHECK(std::hypot(truth->x_m, truth->y_m) < 0.05);
  CHECK(truth->z_m == Approx(0.10).margin(0.05));
  backend->flight().land_and_stop(0);
}
