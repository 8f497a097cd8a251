// `labodrone tello-state FILE` and `labodrone video FILE --protocol tello` on captures and
// recordings: decoded as the link decodes them, exit 2 with one line of reason on junk.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <unistd.h>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/inspect_commands.hpp"
#include "drone/replay/recording.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_state_command.hpp"
#include "tests/drone/ardrone2/fixtures.hpp"
#include "tests/support/cli_run.hpp"

using namespace labo;
using namespace labo::ardrone2;
using namespace labo::replay;
using namespace labo::tello;

namespace {

using test::CliRun;
constexpr auto run = &test::run_command;

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

std::vector<nlohmann::json> json_lines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

// Access units of a 320x240 scene, an IDR every 10.
std::vector<std::vector<std::uint8_t>> units(int count) {
  ardrone2::H264Encoder encoder({.width = 320, .height = 240, .fps = 30, .gop = 10, .bitrate_kbps = 1500});
  cv::Mat image(240, 320, CV_8UC3);
  ardrone2::EncodedFrame frame;
  std::vector<std::vector<std::uint8_t>> out;
  for (int i = 0; i < count; ++i) {
    image.setTo(cv::Scalar(200, 80, 40));
    cv::circle(image, cv::Point(40 + 8 * i, 120), 30, cv::Scalar(255, 255, 255), cv::FILLED);
    REQUIRE(encoder.encode(image, frame));
    out.push_back(frame.data);
  }
  return out;
}

constexpr const char* kState =
    "mid:-1;x:-100;y:-100;z:-100;mpry:-1,-1,-1;pitch:-2;roll:1;yaw:-90;vgx:3;vgy:-1;vgz:0;templ:62;temph:64;"
    "tof:98;h:90;bat:81;baro:-57.14;time:14;agx:17.00;agy:-4.00;agz:-996.00;";

}  // namespace

TEST_CASE("tello: labodrone tello-state decodes a capture and a recording", "[tello][cli]") {
  const auto capture = temp("tello_states.txt");
  test::write_bytes(capture, bytes_of(std::string(kState) + "\r\n\r\npitch:0;roll:0;\r\n" + kState + "\n"));
  auto r = run(run_tello_state_command, tello_state_command_spec(), {capture.string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto lines = json_lines(r.out);
  REQUIRE(lines.size() == 3);
  CHECK(lines[0]["line"] == 1);
  CHECK(lines[0]["state"]["yaw_deg"] == -90.0);
  CHECK(lines[0]["state"]["mission_pad"]["mid"] == -1);
  CHECK(lines[0]["sample"]["yaw_rad"].get<double>() == Approx(1.5708).epsilon(1e-4));
  CHECK(lines[0]["sample"]["altitude_m"].get<double>() == Approx(0.98));
  CHECK(lines[1]["line"] == 3);  // blank lines are skipped, not refused
  CHECK(lines[1]["error"] == "tello_state_missing_field");
  CHECK(lines[1]["detail"] == "missing field 'yaw'");
  CHECK(r.err.find("1 invalid state strings") != std::string::npos);

  const auto recording = temp("tello_states.laborec");
  {
    RecordingWriter w(recording);
    w.write(RecordChannel::TelloStateIn, 2.5, bytes_of(kState));
    w.write(RecordChannel::TelloCommandOut, 2.6, bytes_of("rc 0 0 0 0"));
  }
  r = run(run_tello_state_command, tello_state_command_spec(), {recording.string()});
  REQUIRE(r.code == 0);
  CHECK(json_lines(r.out).at(0)["t"] == 2.5);
  std::filesystem::remove(capture);
  std::filesystem::remove(recording);
}

TEST_CASE("tello: labodrone tello-state exits 2 with a reason on junk", "[tello][cli]") {
  auto r = run(run_tello_state_command, tello_state_command_spec(), {temp("does_not_exist").string()});
  CHECK(r.code == 2);
  CHECK(r.err.find("cannot read") != std::string::npos);
  const auto junk = temp("tello_junk.bin");
  std::vector<std::uint8_t> bytes(3000);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i * 37 + 11);
  test::write_bytes(junk, bytes);
  r = run(run_tello_state_command, tello_state_command_spec(), {junk.string()});
  CHECK(r.code == 2);
  CHECK(r.err.find("no valid Tello state string") != std::string::npos);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  std::filesystem::remove(junk);
}

TEST_CASE("tello: labodrone video --protocol tello decodes a UDP 11111 capture and a recording", "[tello][cli]") {
  const auto stream = units(20);
  std::vector<std::uint8_t> capture_bytes = {9, 9, 9};  // junk before the first start code
  for (const auto& u : stream) capture_bytes.insert(capture_bytes.end(), u.begin(), u.end());
  const auto capture = temp("tello_video.h264");
  test::write_bytes(capture, capture_bytes);
  auto r = run(run_video_command, video_command_spec(), {capture.string(), "--protocol", "tello"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  auto j = nlohmann::json::parse(r.out);
  CHECK(j["input"] == "udp_capture");
  CHECK(j["frames"] == 20);
  CHECK(j["decoded"] == 20);
  CHECK(j["keyframes"] == 2);
  CHECK(j["width"] == 320);
  CHECK(j["height"] == 240);
  CHECK(j["junk_bytes"] == 3);
  CHECK(j["errors"] == 1);  // the junk

  // The same units recorded as TelloLink records its datagrams.
  const auto recording = temp("tello_video.laborec");
  {
    RecordingWriter w(recording);
    double t = 0;
    for (const auto& u : stream) {
      for (std::size_t at = 0; at < u.size(); at += tello::kTelloVideoDatagramBytes)
        w.write(RecordChannel::TelloVideoIn, t += 0.001,
                std::span(u).subspan(at, std::min(tello::kTelloVideoDatagramBytes, u.size() - at)));
    }
  }
  r = run(run_video_command, video_command_spec(), {recording.string()});
  REQUIRE(r.code == 0);
  j = nlohmann::json::parse(r.out);
  CHECK(j["input"] == "recording");
  CHECK(j["decoded"] == 20);
  CHECK(j["errors"] == 0);

  // Junk alone: no access unit, exit 2 with the reason; a protocol it does not know: a usage error.
  const auto junk = temp("tello_video_junk");
  test::write_bytes(junk, std::vector<std::uint8_t>(5000, 0x42));
  r = run(run_video_command, video_command_spec(), {junk.string(), "--protocol", "tello"});
  CHECK(r.code == 2);
  CHECK(r.err.find("no H.264 access unit") != std::string::npos);
  const std::vector<std::string> bebop = {junk.string(), "--protocol", "bebop"};
  CHECK_THROWS_AS(run_video_command(parse_args(video_command_spec(), bebop)), UsageError);
  std::filesystem::remove(capture);
  std::filesystem::remove(recording);
  std::filesystem::remove(junk);
}
