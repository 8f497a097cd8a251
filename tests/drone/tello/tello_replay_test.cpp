// A Tello flight recorded by TelloLink replays through ReplayLink with the same events (the flight
// phase rebuilt from the recorded commands and replies), and a recording's bad input is counted.
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <thread>
#include <unistd.h>
#include <vector>

#include "drone/replay/replay_link.hpp"
#include "drone/tello/tello_emulator.hpp"
#include "drone/tello/tello_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/drone/link_events.hpp"
#include "tests/drone/sim/loopback_support.hpp"

using namespace labo;
using namespace labo::replay;
using namespace labo::tello;

namespace {

using Events = test::LinkEvents;

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".laborec");
}

std::uint64_t count(const LinkStatistics& s, const char* kind) {
  const auto it = s.counters.find(kind);
  return it == s.counters.end() ? 0 : it->second;
}

void write_text(RecordingWriter& w, RecordChannel channel, Seconds t, std::string_view text) {
  w.write(channel, t, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

constexpr const char* kState =
    "pitch:0;roll:0;yaw:0;vgx:0;vgy:0;vgz:0;templ:60;temph:62;tof:10;h:0;bat:90;baro:10.00;time:%d;"
    "agx:0.00;agy:0.00;agz:-1000.00;\r\n";

std::string state_at(int motors_s) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), kState, motors_s);
  return buf;
}

}  // namespace

TEST_CASE("tello: a recorded flight replays with the same events", "[tello][replay]") {
  const auto file = temp_file("labo_tello_replay");
  Events live(true);
  {
    test::TinyVehicle vehicle;
    TelloEmulatorSettings es;
    es.command_port = 0;
    es.video_width = 320;
    es.video_height = 240;
    TelloEmulator emulator(vehicle, es, Logger("test", LogLevel::Off));
    emulator.start();
    TelloLinkSettings ls;
    ls.host = "127.0.0.1";
    ls.command_port = emulator.command_port();
    ls.state_port = ls.video_port = 0;
    ls.recording = file;
    TelloLink link(ls, Logger("test", LogLevel::Off));
    link.set_listener(&live);
    link.open();
    emulator.set_client_ports(link.state_port(), link.video_port());
    link.start();
    REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 5.0));
    link.takeoff();
    REQUIRE(test::eventually([&] { std::lock_guard l(live.m); return live.navdata.back().control_state == 4; }, 5.0));
    link.move(MoveCommand{0.1, 0.2, 0.0, -0.3});
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    link.land();
    REQUIRE(test::eventually([&] { std::lock_guard l(live.m); return live.navdata.back().control_state == 2; }, 5.0));
    link.stop();
    emulator.stop();
  }
  REQUIRE(live.navdata.size() > 10);
  REQUIRE(live.frames.size() > 10);

  Events replayed(true);
  ReplayLink replay(file, Logger("test", LogLevel::Off));
  replay.set_listener(&replayed);
  replay.run_to_end();
  CHECK_FALSE(replay.truncated());
  REQUIRE(replayed.navdata.size() == live.navdata.size());
  std::vector<int> phases;
  for (std::size_t i = 0; i < live.navdata.size(); ++i) {
    INFO("state " << i);
    const NavdataSample &a = replayed.navdata[i], &b = live.navdata[i];
    CHECK(a.t == b.t);
    CHECK(a.sequence == b.sequence);
    CHECK(a.control_state == b.control_state);
    CHECK(a.altitude_m == b.altitude_m);
    CHECK(a.vx_mps == b.vx_mps);
    CHECK(a.yaw_rad == b.yaw_rad);
    if (phases.empty() || phases.back() != b.control_state) phases.push_back(b.control_state);
  }
  CHECK(phases == std::vector<int>{2, 6, 4, 3, 8, 2});  // landed, take-off, hover, fly, landing, landed
  REQUIRE(replayed.frames.size() == live.frames.size());
  for (std::size_t i = 0; i < live.frames.size(); ++i) {
    INFO("frame " << i);
    CHECK(replayed.frames[i].t == live.frames[i].t);
    CHECK(replayed.frames[i].number == live.frames[i].number);
    CHECK(cv::norm(replayed.pixels[i], live.pixels[i], cv::NORM_INF) == 0.0);
  }
  CHECK(replayed.states == live.states);
  CHECK(recorded_drone(file) == RecordedDrone::Tello);  // serve --drone replay: sees it through the Tello's camera
  std::filesystem::remove(file);
}

TEST_CASE("tello: a recording says which drone it holds", "[tello][replay]") {
  const auto file = temp_file("labo_which_drone");
  {
    RecordingWriter w(file);
    w.note(0.0, "link_state connecting");
  }
  CHECK(recorded_drone(file) == RecordedDrone::Unknown);
  {
    RecordingWriter w(file);
    w.note(0.0, "link_state connecting");
    write_text(w, RecordChannel::NavdataOut, 0.1, std::string("\x01\0\0\0", 4));
  }
  CHECK(recorded_drone(file) == RecordedDrone::Ardrone);
  std::filesystem::remove(file);
}

TEST_CASE("tello: a recording's replies to nothing and malformed states are counted on replay", "[tello][replay]") {
  const auto file = temp_file("labo_tello_bad_replay");
  {
    RecordingWriter w(file);
    write_text(w, RecordChannel::TelloReplyIn, 0.05, "ok");  // before any command: a reply to nothing
    write_text(w, RecordChannel::TelloCommandOut, 0.1, "command");
    write_text(w, RecordChannel::TelloReplyIn, 0.12, "ok");
    write_text(w, RecordChannel::TelloStateIn, 0.2, state_at(0));
    write_text(w, RecordChannel::TelloStateIn, 0.3, "pitch:0;roll:0;");  // malformed: fields missing
    write_text(w, RecordChannel::TelloCommandOut, 0.4, "takeoff");
    write_text(w, RecordChannel::TelloStateIn, 0.5, state_at(1));
    write_text(w, RecordChannel::TelloStateIn, 1.2, state_at(2));
    write_text(w, RecordChannel::TelloStateIn, 1.9, state_at(3));
    w.note(2.0, std::string(kNoteTelloGaveUpPrefix) + "timed_out takeoff");  // no reply, but the motors run
    write_text(w, RecordChannel::TelloStateIn, 2.1, state_at(3));
    write_text(w, RecordChannel::TelloCommandOut, 2.2, "rc 0 40 0 0");
    write_text(w, RecordChannel::TelloStateIn, 2.3, state_at(3));
    write_text(w, RecordChannel::TelloReplyIn, 2.4, std::string("o\x01k", 3));  // not text
    write_text(w, RecordChannel::TelloVideoIn, 2.5, "junk that holds no start code");
  }
  Events e;
  ReplayLink replay(file, Logger("test", LogLevel::Off));
  replay.set_listener(&e);
  replay.run_to_end();
  std::vector<int> phases;
  for (const auto& n : e.navdata) phases.push_back(n.control_state);
  // landed; taking off; the take-off timed out but the motors' time grew: hovering; sticks off centre: flying
  CHECK(phases == std::vector<int>{2, 6, 6, 6, 4, 3});
  const auto stats = replay.statistics();
  CHECK(recorded_drone(file) == RecordedDrone::Tello);
  CHECK(count(stats, "tello_reply_unsolicited") == 1);
  CHECK(count(stats, "tello_state_missing_field") == 1);
  CHECK(count(stats, "tello_reply_not_text") == 1);
  CHECK(count(stats, "tello_video_junk") == 1);
  std::filesystem::remove(file);
}
