#include <catch2/catch.hpp>

#include <filesystem>
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
