#include <catch2/catch.hpp>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "drone/ardrone2/inspect_commands.hpp"
#include "tests/drone/ardrone2/fixtures.hpp"
#include "tests/support/cli_run.hpp"

using namespace labo;
using namespace labo::ardrone2;

namespace {

using test::CliRun;
constexpr auto run = &test::run_command;

CliRun navdata(const std::filesystem::path& f) { return run(run_navdata_command, navdata_command_spec(), {f.string()}); }

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

}  // namespace

TEST_CASE("link: labodrone navdata prints the committed captures", "[link][cli]") {
  const auto dir = test::fixture_dir();
  auto r = navdata(dir / "navdata_demo.bin");
  REQUIRE(r.code == 0);
  auto j = nlohmann::json::parse(r.out);
  CHECK(j["sequence"] == 4242);
  CHECK(j["checksum_ok"] == true);
  CHECK(j["state_flags"]["flying"] == true);
  CHECK(j["state_flags"]["navdata_demo"] == true);
  CHECK(j["state_flags"].size() == 32);
  CHECK(j["demo"]["control_state"] == "hovering");
  CHECK(j["demo"]["theta_deg"].get<double>() == Approx(-2.15));
  CHECK(j["demo"]["raw"]["theta"].get<double>() == Approx(-2150.0));
  CHECK(j["demo"]["altitude_m"].get<double>() == Approx(1.012));
  CHECK(j["demo"]["vx_mps"].get<double>() == Approx(0.3105));
  CHECK(j["demo"]["battery_percent"] == 76);
  CHECK(j.contains("vision_detect"));
  CHECK(test::read_bytes(dir / "navdata_demo.bin").size() == 500);  // the default demo packet size

  r = navdata(dir / "navdata_full.bin");
  REQUIRE(r.code == 0);
  j = nlohmann::json::parse(r.out);
  CHECK(j["raw_measures"]["vbat_raw_mv"] == 12250);
  CHECK(j.contains("gps"));
  CHECK(j.contains("wind_speed"));
  CHECK(j["unknown_options"][0]["tag"] == 28);

  r = navdata(dir / "navdata_bootstrap_real.bin");
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(r.out)["state_flags"]["navdata_bootstrap"] == true);
}

TEST_CASE("link: labodrone navdata exits 2 with a reason on bad input", "[link][cli]") {
  auto r = navdata(temp("does_not_exist"));
  CHECK(r.code == 2);
  CHECK(r.err.find("cannot read") != std::string::npos);
  auto bytes = test::demo_packet();
  bytes[40] ^= 0x10;
  const auto f = temp("bad_cks");
  test::write_bytes(f, bytes);
  r = navdata(f);
  CHECK(r.code == 2);
  CHECK(r.err.find("navdata_bad_checksum") != std::string::npos);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(nlohmann::json::parse(r.out)["checksum_ok"] == false);  // still shown, flagged
  bytes.resize(10);
  test::write_bytes(f, bytes);
  r = navdata(f);
  CHECK(r.code == 2);
  CHECK(r.err.find("navdata_truncated") != std::string::npos);
  std::filesystem::remove(f);
}

TEST_CASE("link: labodrone video summarises a capture and writes frames", "[link][cli]") {
  const auto frames_dir = temp("video_frames");
  auto r = run(run_video_command, video_command_spec(),
               {(test::fixture_dir() / "video_capture.bin").string(), "--frames", frames_dir.string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["frames"] == 20);
  CHECK(j["decoded"] == 20);
  CHECK(j["keyframes"] == 2);
  CHECK(j["codec"] == "h264");
  CHECK(j["width"] == 640);
  CHECK(j["height"] == 360);
  CHECK(j["errors"] == 1);  // the junk before frame 5
  CHECK(j["frames_written"] == 20);
  CHECK(std::filesystem::exists(frames_dir / "frame_000019.png"));
  std::filesystem::remove_all(frames_dir);

  const auto junk = temp("junk_video");
  test::write_bytes(junk, std::vector<std::uint8_t>(5000, 0x42));
  r = run(run_video_command, video_command_spec(), {junk.string()});
  CHECK(r.code == 2);
  CHECK(r.err.find("no PaVE frame") != std::string::npos);
  std::filesystem::remove(junk);
}
