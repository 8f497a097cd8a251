#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <unistd.h>
#include <thread>
#include <vector>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/ardrone2/inspect_commands.hpp"
#include "drone/replay/replay_link.hpp"
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/drone/link_events.hpp"

using namespace labo;
using namespace labo::ardrone2;
using namespace labo::replay;

namespace {

using Events = test::LinkEvents;

bool same(const NavdataSample& a, const NavdataSample& b) {
  return a.t == b.t && a.sequence == b.sequence && a.state == b.state && a.control_state == b.control_state &&
         a.battery_percent == b.battery_percent && a.roll_rad == b.roll_rad && a.pitch_rad == b.pitch_rad &&
         a.yaw_rad == b.yaw_rad && a.altitude_m == b.altitude_m && a.vx_mps == b.vx_mps && a.vy_mps == b.vy_mps &&
         a.vz_mps == b.vz_mps && a.has_drone_time == b.has_drone_time && a.drone_time == b.drone_time;
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".laborec");
}

}  // namespace

TEST_CASE("link: record then replay yields identical events", "[link][replay]") {
  const auto file = temp_file("labo_record_replay");
  Events live(true);  // the pixels kept by reference: the receiver must then not reuse its buffer
  {
    test::TinyVehicle vehicle;
    ArdroneEmulatorSettings es;
    es.at_port = es.navdata_port = es.video_port = 0;
    es.camera_switch_delay_s = 0.1;
    es.com_watchdog_s = 0.5;
    ArdroneEmulator emulator(vehicle, es, Logger("test", LogLevel::Off));
    emulator.start();
    ArdroneLinkSettings ls = test::link_settings_for(emulator);
    ls.recording = file;
    ArdroneLink link(ls, Logger("test", LogLevel::Off));
    link.set_listener(&live);
    link.start();
    link.takeoff();
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    link.select_camera(CameraId::Bottom);
    link.move(MoveCommand{0.1, 0.2, 0.0, -0.3});
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    link.land();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    link.stop();
    emulator.stop();
    // Every byte the writer reported is on disk once the link has stopped.
    CHECK(link.recorded_bytes() > 1000);
    CHECK(std::filesystem::file_size(file) == link.recorded_bytes());
  }
  REQUIRE(live.navdata.size() > 10);
  REQUIRE(live.frames.size() > 10);

  Events replayed(true);
  ReplayLink replay(file, Logger("test", LogLevel::Off));
  replay.set_listener(&replayed);
  replay.run_to_end();
  CHECK_FALSE(replay.truncated());

  REQUIRE(replayed.navdata.size() == live.navdata.size());
  for (std::size_t i = 0; i < live.navdata.size(); ++i) {
    INFO("navdata " << i);
    CHECK(same(replayed.navdata[i], live.navdata[i]));
  }
  REQUIRE(replayed.frames.size() == live.frames.size());
  bool saw_bottom = false;
  for (std::size_t i = 0; i < live.frames.size(); ++i) {
    INFO("frame " << i);
    CHECK(replayed.frames[i].t == live.frames[i].t);
    CHECK(replayed.frames[i].number == live.frames[i].number);
    CHECK(replayed.frames[i].camera == live.frames[i].camera);
    saw_bottom = saw_bottom || live.frames[i].camera == CameraId::Bottom;
    REQUIRE(replayed.pixels[i].size() == live.pixels[i].size());
    CHECK(cv::norm(replayed.pixels[i], live.pixels[i], cv::NORM_INF) == 0.0);
  }
  CHECK(saw_bottom);
  CHECK(replayed.states == live.states);

  // The inspection commands read recordings too.
  std::ostringstream out, err;
  auto* old_out = std::cout.rdbuf(out.rdbuf());
  auto* old_err = std::cerr.rdbuf(err.rdbuf());
  const int video_rc = run_video_command(parse_args(video_command_spec(), std::vector<std::string>{file.string()}));
  const std::string video_json = out.str();
  out.str("");
  const int navdata_rc = run_navdata_command(parse_args(navdata_command_spec(), std::vector<std::string>{file.string()}));
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  INFO(err.str());
  CHECK(video_rc == 0);
  CHECK(nlohmann::json::parse(video_json)["decoded"] == live.frames.size());
  CHECK(navdata_rc == 0);
  std::size_t lines = 0;
  for (char c : out.str()) lines += c == '\n';
  CHECK(lines >= live.navdata.size());  // every navdata datagram, bootstrap ones included
  std::filesystem::remove(file);
}

TEST_CASE("link: recording reader refuses bad files and stops at a truncated record", "[link][replay]") {
  const auto file = temp_file("labo_bad_recording");
  {
    std::ofstream out(file, std::ios::binary);
    out << "not a recording at all";
  }
  CHECK_THROWS_WITH(RecordingReader(file), Catch::Contains("LABOREC1"));
  {
    RecordingWriter w(file);
    const std::vector<std::uint8_t> bytes = {1, 2, 3, 4, 5};
    w.write(RecordChannel::NavdataIn, 1.5, bytes);
    w.write(RecordChannel::VideoIn, 2.0, bytes);
  }
  // Cut the last record in the middle.
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 2);
  RecordingReader r(file);
  Record rec;
  REQUIRE(r.next(rec));
  CHECK(rec.channel == RecordChannel::NavdataIn);
  CHECK(rec.t == 1.5);
  CHECK(rec.bytes.size() == 5);
  CHECK_FALSE(r.next(rec));
  CHECK(r.truncated());
  {
    std::ofstream out(file, std::ios::binary | std::ios::app);
  }
  // An unknown channel is an error naming the record.
  {
    RecordingWriter w(file);
    w.write(static_cast<RecordChannel>(10), 0.0, std::vector<std::uint8_t>{});  // 1-9 are defined
  }
  RecordingReader bad(file);
  CHECK_THROWS_WITH(bad.next(rec), Catch::Contains("unknown channel"));
  std::filesystem::remove(file);
}

TEST_CASE("recording: a chunk longer than a record is kept whole in consecutive records", "[replay]") {
  const auto file = temp_file("labo_long_chunk");
  std::vector<std::uint8_t> bytes(kMaxRecordBytes + 10);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i * 7);
  {
    RecordingWriter w(file);
    w.write(RecordChannel::VideoIn, 3.0, bytes);
  }
  RecordingReader r(file);
  Record rec;
  std::vector<std::uint8_t> back;
  int records = 0;
  while (r.next(rec)) {
    CHECK(rec.channel == RecordChannel::VideoIn);
    CHECK(rec.t == 3.0);
    back.insert(back.end(), rec.bytes.begin(), rec.bytes.end());
    ++records;
  }
  CHECK_FALSE(r.truncated());
  CHECK(records == 2);
  CHECK(back == bytes);
  std::filesystem::remove(file);
}
