// TelloLink flies a tiny vehicle through TelloEmulator over loopback: SDK mode, the state string, the
// sticks and their signs, take-off and landing answered when done, H.264 over UDP, link loss and
// recovery, the drone's 15 s watchdog, and junk on the state and video ports. (A reply to no command
// is tested through a recording: tests/drone/tello/tello_replay_test.cpp.)
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "drone/tello/tello_emulator.hpp"
#include "drone/tello/tello_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/drone/link_events.hpp"
#include "tests/drone/sim/loopback_support.hpp"

using namespace labo;
using namespace labo::tello;

namespace {

using Recorder = test::LinkEvents;

Logger quiet() { return Logger("test", LogLevel::Off); }

std::uint64_t count(const LinkStatistics& s, const char* kind) {
  const auto it = s.counters.find(kind);
  return it == s.counters.end() ? 0 : it->second;
}

TelloEmulatorSettings emulator_settings() {
  TelloEmulatorSettings es;
  es.command_port = 0;
  es.video_width = 480;  // small frames: the tests are about the protocol
  es.video_height = 360;
  return es;
}

// A link on free ports, pointed at the emulator, the emulator told where the link listens.
TelloLinkSettings link_settings(const TelloEmulator& emulator) {
  TelloLinkSettings ls;
  ls.host = "127.0.0.1";
  ls.command_port = emulator.command_port();
  ls.state_port = ls.video_port = 0;
  return ls;
}

void connect(TelloLink& link, TelloEmulator& emulator) {
  link.open();
  emulator.set_client_ports(link.state_port(), link.video_port());
  link.start();
}

// A tiny vehicle behind the emulator, and the link connected to it.
struct Flight {
  test::TinyVehicle vehicle;
  TelloEmulator emulator{vehicle, emulator_settings(), quiet()};
  Recorder rec;  // before the link: it outlives the link's last event
  std::unique_ptr<TelloLink> link;
  Flight() {
    emulator.start();
    link = std::make_unique<TelloLink>(link_settings(emulator), quiet());
    link->set_listener(&rec);
    connect(*link, emulator);
  }
};

}  // namespace

TEST_CASE("tello: the link takes off, flies, streams and lands a vehicle through the emulator", "[tello][loopback]") {
  Flight f;
  auto& [vehicle, emulator, rec, link_ptr] = f;
  TelloLink& link = *link_ptr;
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 5.0));
  // The state thread marks the link alive before its listener hears the sample: wait for the sample.
  REQUIRE(test::eventually([&] { return rec.last().battery_percent > 0; }, 2.0));
  CHECK(rec.last().battery_percent == Approx(80));
  CHECK(rec.last().control_state == 2);
  REQUIRE(test::eventually([&] { return rec.frame_count() >= 5; }, 10.0));
  {
    std::lock_guard l(rec.m);
    CHECK(rec.frames.back().width == 480);
    CHECK(rec.frames.back().height == 360);
    CHECK(rec.frames.back().camera == CameraId::Front);
    CHECK(cv::mean(rec.last_pixels)[2] > 150);  // the tiny vehicle's front view is red
  }

  link.flat_trim();  // not in the SDK: counted, nothing sent
  link.takeoff();
  REQUIRE(test::eventually([&] { return rec.last().control_state == 6; }, 2.0));
  REQUIRE(test::eventually([&] { return rec.last().control_state == 4 && rec.last().altitude_m > 0.7; }, 5.0));

  // Forward and counter-clockwise in LaboDrone's signs: the vehicle sees the same after "rc".
  link.move(MoveCommand{0.0, 0.5, 0.0, 0.4});
  REQUIRE(test::eventually([&] { return vehicle.snapshot().x_m > 0.3; }, 5.0));
  CHECK(vehicle.snapshot().last_move.pitch == Approx(0.5));
  CHECK(vehicle.snapshot().last_move.yaw_rate == Approx(0.4));
  REQUIRE(test::eventually([&] { return rec.last().vx_mps > 0.3; }, 2.0));
  CHECK(rec.last().control_state == 3);  // sticks off centre: flying
  CHECK(rec.last().yaw_rad > 0.0);
  link.move(MoveCommand{-0.5, 0.0, 0.0, 0.0});
  REQUIRE(test::eventually([&] { return rec.last().vy_mps > 0.3; }, 2.0));  // roll < 0 = left = +y
  link.hover();
  REQUIRE(test::eventually([&] { return vehicle.snapshot().hovering; }, 2.0));

  // The bottom camera is the Tello EDU's downward camera: "downvision 1", then its grey 320x240
  // pictures labelled Bottom; "downvision 0" brings the front camera back.
  link.select_camera(CameraId::Bottom);
  REQUIRE(test::eventually([&] { return rec.last_frame().camera == CameraId::Bottom; }, 5.0));
  {
    std::lock_guard l(rec.m);
    CHECK(rec.frames.back().width == 320);
    CHECK(rec.frames.back().height == 240);
    const cv::Scalar mean = cv::mean(rec.last_pixels);
    CHECK(std::abs(mean[0] - mean[2]) < 3.0);  // grey: the tiny vehicle's green bottom view without its colour
  }
  link.select_camera(CameraId::Front);
  REQUIRE(test::eventually([&] { return rec.last_frame().camera == CameraId::Front && rec.last_frame().width == 480; }, 5.0));
  CHECK_THROWS_WITH(link.set_config("video:video_channel", "1"), Catch::Contains("'speed'"));
  link.set_config("speed", "50");

  link.land();
  REQUIRE(test::eventually([&] { return rec.last().control_state == 2; }, 5.0));
  CHECK(rec.last().altitude_m == Approx(0.0).margin(0.01));
  const auto stats = link.statistics();
  CHECK(count(stats, "tello_bottom_camera_unavailable") == 0);
  CHECK(count(stats, "tello_flat_trim_not_in_sdk") == 1);
  CHECK(count(stats, "state_packets") > 10);
  CHECK(count(stats, "rc_sent") > 10);
  CHECK(count(stats, "tello_command_timed_out") == 0);
  CHECK(count(stats, "tello_reply_unsolicited") == 0);
  CHECK(count(stats, "tello_command_refused") == 0);
  CHECK(count(emulator.statistics(), "sdk_mode_entered") == 1);
  link.stop();
  emulator.stop();
  std::lock_guard l(rec.m);
  CHECK(rec.states.front().first == LinkState::Connecting);
  CHECK(rec.states.back().first == LinkState::Disconnected);
}

TEST_CASE("tello: a Tello without the downward camera refuses downvision: counted, logged, frames stay front", "[tello][loopback]") {
  test::TinyVehicle vehicle;
  TelloEmulatorSettings es = emulator_settings();
  es.firmware.downvision = false;  // a plain Tello
  TelloEmulator emulator(vehicle, es, quiet());
  emulator.start();
  Recorder rec;
  TelloLink link(link_settings(emulator), quiet());
  link.set_listener(&rec);
  connect(link, emulator);
  REQUIRE(test::eventually([&] { return rec.frame_count() >= 3; }, 10.0));
  link.select_camera(CameraId::Bottom);
  REQUIRE(test::eventually([&] { return count(link.statistics(), "tello_downvision_refused") == 1; }, 5.0));
  link.select_camera(CameraId::Bottom);  // from now on refused by the link itself, nothing sent
  const std::size_t frames_before = rec.frame_count();
  REQUIRE(test::eventually([&] { return rec.frame_count() > frames_before + 3; }, 5.0));
  CHECK(rec.last_frame().camera == CameraId::Front);
  const auto stats = link.statistics();
  CHECK(count(stats, "tello_bottom_camera_unavailable") == 1);
  CHECK(count(emulator.statistics(), "downvision_unsupported") == 1);
  link.stop();
  emulator.stop();
}

TEST_CASE("tello: supervision marks the link degraded, lost, and enters SDK mode again", "[tello][loopback]") {
  test::TinyVehicle vehicle;
  TelloEmulatorSettings es = emulator_settings();
  auto emulator = std::make_unique<TelloEmulator>(vehicle, es, quiet());
  emulator->start();
  TelloLinkSettings ls = link_settings(*emulator);
  ls.video = false;
  ls.degraded_after_s = 0.3;
  ls.lost_after_s = 0.8;
  ls.reply_timeout_s = 0.2;
  TelloLink link(ls, quiet());
  Recorder rec;
  link.set_listener(&rec);
  connect(link, *emulator);
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 5.0));
  // The drone goes away...
  es.command_port = ls.command_port;
  es.client_state_port = link.state_port();
  es.client_video_port = link.video_port();
  emulator.reset();
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Lost; }, 5.0));
  CHECK(rec.saw(LinkState::Degraded));
  // ...and comes back, fresh from a reboot (outside SDK mode): the link knocks with "command" again.
  emulator = std::make_unique<TelloEmulator>(vehicle, es, quiet());
  emulator->start();
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 5.0));
  CHECK(count(link.statistics(), "reconnects") == 1);
  CHECK(count(emulator->statistics(), "sdk_mode_entered") == 1);
  link.stop();
}

TEST_CASE("tello: the emulated drone answers as a Tello and lands by itself after its watchdog", "[tello][loopback]") {
  // A raw client (any Tello program) with the watchdog shortened from 15 s to 1 s.
  test::TinyVehicle vehicle;
  TelloEmulatorSettings es = emulator_settings();
  es.firmware.watchdog_s = 1.0;
  TelloEmulator emulator(vehicle, es, quiet());
  emulator.start();
  ardrone2::Socket client = ardrone2::Socket::udp(0, "127.0.0.1");
  const auto to = ardrone2::Endpoint::resolve("127.0.0.1", emulator.command_port());
  auto send = [&](std::string_view text) {
    client.send_to(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), to);
  };
  auto reply = [&](double timeout_s = 5.0) {
    std::array<std::uint8_t, 256> buffer;
    ardrone2::Endpoint from;
    const long n = client.receive_from(buffer, from, timeout_s);
    return n < 0 ? std::string("(none)") : std::string(reinterpret_cast<const char*>(buffer.data()), static_cast<std::size_t>(n));
  };
  send("takeoff");  // outside SDK mode a Tello ignores text
  CHECK(reply(0.3) == "(none)");
  send("command");
  CHECK(reply() == "ok");
  send("battery?");
  CHECK(reply() == "80");
  send("sdk?");
  CHECK(reply() == "20");
  send("takeoff");
  CHECK(reply() == "ok");  // once hovering
  CHECK(vehicle.snapshot().flying);
  send("takeoff");
  CHECK(reply() == "error");  // already flying
  send("forward 19");
  CHECK(reply() == "error distance out of range [20, 500]");  // the SDK's range, with the reason
  send("jump 100 100 100 40 90 m1 m2");
  CHECK(reply() == "error");  // the mission pads' moves this emulator does not fly: refused, counted
  send("hello");
  CHECK(reply() == "error");
  send("rc 1 2");
  CHECK(reply(0.3) == "(none)");  // rc is never answered, malformed or not
  send("rc 0 30 0 0");
  REQUIRE(test::eventually([&] { return vehicle.snapshot().last_move.pitch > 0.29; }, 2.0));
  // Then silence: the watchdog lands the vehicle.
  REQUIRE(test::eventually([&] { return !vehicle.snapshot().flying; }, 5.0));
  const auto stats = emulator.statistics();
  CHECK(count(stats, "watchdog_landings") == 1);
  CHECK(count(stats, "commands_before_sdk_mode") == 1);
  CHECK(count(stats, "unflown_commands") == 1);
  CHECK(count(stats, "unknown_command") == 1);
  CHECK(count(stats, "rc_malformed") == 1);
}

TEST_CASE("tello: junk on the state and video ports is counted, never fatal", "[tello][loopback]") {
  Flight f;
  TelloLink& link = *f.link;
  Recorder& rec = f.rec;
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected && rec.frame_count() > 2; }, 10.0));

  ardrone2::Socket junk = ardrone2::Socket::udp(0, "127.0.0.1");
  auto to_port = [](int port) { return ardrone2::Endpoint::resolve("127.0.0.1", port); };
  const std::vector<std::uint8_t> bytes = {0xde, 0xad, 0xbe, 0xef, 0, 0, 1, 0x65, 0x88, 0x00, 0x13};
  const std::string bad_state = "pitch:0;roll:0;yaw:x;";
  for (int i = 0; i < 20; ++i) {
    junk.send_to(bytes, to_port(link.video_port()));
    junk.send_to(std::span(reinterpret_cast<const std::uint8_t*>(bad_state.data()), bad_state.size()),
                 to_port(link.state_port()));
  }
  REQUIRE(test::eventually([&] {
    const auto s = link.statistics();
    return count(s, "tello_state_bad_number") == 20;
  }, 5.0));
  const std::size_t frames = rec.frame_count();
  REQUIRE(test::eventually([&] { return rec.frame_count() > frames + 5; }, 5.0));  // the video goes on
  CHECK(link.state() == LinkState::Connected);
  const auto s = link.statistics();
  CHECK(count(s, "tello_video_junk") + count(s, "h264_decode_error") > 0);
  link.stop();
}
