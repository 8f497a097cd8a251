// The driver flies a tiny vehicle through the emulator over loopback: the whole AR.Drone 2.0
// protocol (AT, navdata start-up and config handshake, PaVE/H.264) and the sign conventions end to end.
#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/ardrone2/drone_restart_watch.hpp"
#include "drone/ardrone2/navdata_parser.hpp"
#include "drone/ardrone2/navdata_schema.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/drone/link_events.hpp"

using namespace labo;
using namespace labo::ardrone2;

namespace {

using Recorder = test::LinkEvents;

template <typename Pred>
bool wait_until(Pred pred, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

Logger quiet() { return Logger("test", LogLevel::Off); }

}  // namespace

TEST_CASE("link: the driver takes off, flies, streams and lands a vehicle through the emulator", "[link][loopback]") {
  test::TinyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.camera_switch_delay_s = 0.2;
  es.com_watchdog_s = 0.5;  // a loaded machine delays the AT loop: keep the watchdog bit quiet
  ArdroneEmulator emulator(vehicle, es, quiet());
  emulator.start();

  ArdroneLinkSettings ls = test::link_settings_for(emulator);
  ArdroneLink link(ls, quiet());
  Recorder rec;
  link.set_listener(&rec);
  link.start();

  // Start-up: bootstrap, then navdata_demo acknowledged, then demo packets.
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  REQUIRE(wait_until([&] { return rec.last().state & (1u << 10); }, 5.0));  // navdata_demo bit
  CHECK((rec.last().state & (1u << 11)) == 0);                              // bootstrap over
  CHECK(wait_until([&] { return link.statistics().counters.count("config_acked") == 1; }, 2.0));
  CHECK(rec.last().battery_percent == Approx(80));

  link.flat_trim();
  link.takeoff();
  REQUIRE(wait_until([&] { return rec.last().control_state == 4 && rec.last().altitude_m > 0.7; }, 5.0));
  CHECK(vehicle.snapshot().flat_trims == 1);

  // Forward (pitch > 0 in LaboDrone) and a counter-clockwise turn: the vehicle must see the same signs
  // after the trip through the AR.Drone's wire conventions, and the navdata must report them back.
  link.move(MoveCommand{0.0, 0.5, 0.0, 0.4});
  REQUIRE(wait_until([&] { return vehicle.snapshot().x_m > 0.3; }, 5.0));
  const auto snap = vehicle.snapshot();
  CHECK(snap.last_move.pitch == Approx(0.5));
  CHECK(snap.last_move.yaw_rate == Approx(0.4));
  CHECK(snap.yaw_rad > 0.0);
  REQUIRE(wait_until([&] { return rec.last().vx_mps > 0.3; }, 2.0));
  CHECK(rec.last().pitch_rad > 0.0);  // nose down while flying forward
  CHECK(rec.last().yaw_rad > 0.0);    // counter-clockwise
  link.move(MoveCommand{-0.5, 0.0, 0.0, 0.0});
  REQUIRE(wait_until([&] { return rec.last().vy_mps > 0.3; }, 2.0));  // roll < 0 = left = +y
  CHECK(rec.last().roll_rad < 0.0);
  link.hover();
  REQUIRE(wait_until([&] { return vehicle.snapshot().hovering; }, 2.0));

  // Video: 640x360 frames from the front camera, then the bottom one after the switch.
  REQUIRE(wait_until([&] { std::lock_guard l(rec.m); return rec.frames.size() >= 10; }, 10.0));
  {
    std::lock_guard l(rec.m);
    const auto& f = rec.frames.back();
    CHECK(f.width == 640);
    CHECK(f.height == 360);
    CHECK(f.camera == CameraId::Front);
    CHECK(cv::mean(rec.last_pixels)[2] > 150);  // the front view is red
  }
  link.select_camera(CameraId::Bottom);
  REQUIRE(wait_until([&] {
    std::lock_guard l(rec.m);
    const auto& f = rec.frames.back();
    return f.camera == CameraId::Bottom && cv::mean(rec.last_pixels)[1] > 150;  // the bottom view is green
  }, 10.0));

  link.land();
  REQUIRE(wait_until([&] { return rec.last().control_state == 2; }, 5.0));
  CHECK(rec.last().altitude_m == Approx(0.0).margin(0.01));
  const auto stats = link.statistics();
  CHECK(stats.counters.count("navdata_bad_checksum") == 0);
  CHECK(stats.counters.at("navdata_packets") > 10);
  CHECK(stats.counters.at("video_decoded") >= 10);
  link.stop();
  emulator.stop();
  std::lock_guard l(rec.m);
  CHECK(rec.states.front().first == LinkState::Connecting);
  CHECK(rec.states.back().first == LinkState::Disconnected);
}

TEST_CASE("link: supervision marks the link degraded, lost, and reconnects", "[link][loopback]") {
  test::TinyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.5;
  auto emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  ArdroneLinkSettings ls = test::link_settings_for(*emulator);
  ls.video = false;
  ls.degraded_after_s = 0.3;
  ls.lost_after_s = 0.8;
  ArdroneLink link(ls, quiet());
  Recorder rec;
  link.set_listener(&rec);
  link.start();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  // The drone goes away...
  es.at_port = ls.at_port;
  es.navdata_port = ls.navdata_port;
  es.video_port = ls.video_port;
  emulator.reset();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Lost; }, 5.0));
  CHECK(rec.saw(LinkState::Degraded));
  // ...and comes back on the same ports: the link reconnects without a restart.
  emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  REQUIRE(wait_until([&] { return (rec.last().state & (1u << 11)) == 0; }, 5.0));  // config sent again
  CHECK(link.statistics().counters.at("reconnects") == 1);
  link.stop();
}

TEST_CASE("link: a drone restarted faster than the link's loss is configured again", "[link][loopback]") {
  test::TinyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.5;
  auto emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  ArdroneLinkSettings ls = test::link_settings_for(*emulator);
  ls.video = false;
  ls.lost_after_s = 10.0;  // the restart below is over long before the link would count as lost
  ArdroneLink link(ls, quiet());
  Recorder rec;
  link.set_listener(&rec);
  link.start();
  REQUIRE(wait_until([&] { return rec.last().battery_percent > 0; }, 5.0));
  const std::size_t before = rec.navdata.size();
  // A battery swap: the drone is off for a moment and boots again on the same ports, in bootstrap mode.
  es.at_port = ls.at_port;
  es.navdata_port = ls.navdata_port;
  es.video_port = ls.video_port;
  emulator.reset();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  // The driver sees the bootstrap packets, configures the drone again, and demo navdata (with the
  // battery) comes back; the link was never lost.
  REQUIRE(wait_until([&] { return link.statistics().counters.count("drone_restarts") == 1; }, 5.0));
  REQUIRE(wait_until(
      [&] {
        std::lock_guard l(rec.m);
        return rec.navdata.size() > before + 5 && (rec.navdata.back().state & (1u << 10)) && rec.navdata.back().battery_percent > 0;
      },
      5.0));
  CHECK_FALSE(rec.saw(LinkState::Lost));
  CHECK(link.statistics().counters.count("reconnects") == 0);
  CHECK(link.statistics().counters.at("drone_restarts") == 1);
  link.stop();
}

TEST_CASE("link: navdata whose sequence starts again is a restarted drone, a packet overtaken is not", "[link]") {
  ardrone2::NavdataSequenceFilter f;
  ardrone2::NavdataPacket p;
  p.sequence = 5000;
  REQUIRE(f.accept(p));
  p.sequence = 4990;  // overtaken by a later one
  CHECK_FALSE(f.accept(p));
  CHECK_FALSE(f.restarted());
  p.sequence = 1;  // a drone counting from the start again
  CHECK(f.accept(p));
  CHECK(f.restarted());
  p.sequence = 2;
  CHECK(f.accept(p));
  CHECK_FALSE(f.restarted());
}

TEST_CASE("link: the restart watch fires once when a configured drone streams in bootstrap mode again", "[link]") {
  ardrone2::DroneRestartWatch watch(true);
  ardrone2::NavdataPacket bootstrap;
  bootstrap.state = ardrone2::state_mask(ardrone2::kStateBootstrap);
  ardrone2::NavdataPacket demo;
  demo.add_option(ardrone2::kTagDemo);
  CHECK_FALSE(watch.restarted(bootstrap, false));  // start-up: not yet configured
  CHECK_FALSE(watch.restarted(demo, false));
  CHECK(watch.configured());
  CHECK(watch.restarted(bootstrap, false));        // the drone rebooted
  CHECK_FALSE(watch.restarted(bootstrap, false));  // once, not at every bootstrap packet
  CHECK_FALSE(watch.restarted(demo, false));       // configured again
  CHECK(watch.restarted(demo, true));              // its sequence started again
  watch.configuring();
  CHECK_FALSE(watch.restarted(bootstrap, false));  // a reconnection queued the configuration already
}

TEST_CASE("link: the com-watchdog bit gets COMWDG answers and CALIB reaches the drone", "[link][loopback]") {
  test::TinyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.01;  // shorter than the 30 ms AT period: the bit is set most of the time
  ArdroneEmulator emulator(vehicle, es, quiet());
  emulator.start();
  ArdroneLinkSettings ls = test::link_settings_for(emulator);
  ls.video = false;
  struct OffsetClock final : Clock {  // a caller-provided clock stamps the events
    SteadyClock steady;
    Seconds now() const override { return 1000.0 + steady.now(); }
  } clock;
  ArdroneLink link(ls, quiet(), &clock);
  Recorder rec;
  link.set_listener(&rec);
  link.start();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  // Samples reach the listener once the demo option comes (bootstrap packets carry no values).
  REQUIRE(wait_until([&] { return rec.last().t > 0.0; }, 5.0));
  CHECK(rec.last().t >= 1000.0);
  link.calibrate_magnetometer();
  auto count = [](const LinkStatistics& s, const char* k) { return s.counters.count(k) ? s.counters.at(k) : 0; };
  CHECK(wait_until([&] { return count(emulator.statistics(), "at_COMWDG") > 0; }, 3.0));
  CHECK(count(link.statistics(), "at_comwdg") > 0);
  CHECK(wait_until([&] { return count(emulator.statistics(), "at_CALIB") == 1; }, 2.0));
  link.stop();
}

namespace {
// Detail that moves every frame, so the encoder's bit rate, not the picture, sets the frame size.
struct BusyVehicle : test::TinyVehicle {
  cv::Mat texture = cv::Mat(400, 700, CV_8UC3);
  int frame = 0;
  BusyVehicle() { cv::randu(texture, cv::Scalar::all(0), cv::Scalar::all(255)); }
  void render(CameraId, cv::Mat& bgr) override {
    ++frame;
    texture(cv::Rect(frame % 50, (2 * frame) % 40, 640, 360)).copyTo(bgr);
  }
};

// Mean encoded bytes per frame the driver receives over `seconds`.
double bytes_per_frame(const ArdroneLink& link, double seconds) {
  const auto before = link.statistics().counters;
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const auto after = link.statistics().counters;
  const double frames = static_cast<double>(after.at("video_frames") - before.at("video_frames"));
  return frames > 0 ? static_cast<double>(after.at("video_bytes") - before.at("video_bytes")) / frames : 0.0;
}
}  // namespace

TEST_CASE("link: the driver sets the video bit rate at connect and the emulator's encoder follows", "[link][loopback]") {
  BusyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.5;
  ArdroneEmulator emulator(vehicle, es, quiet());
  REQUIRE(emulator.video_bitrate_kbps() == 1000);  // the firmware's default until a client sets it
  emulator.start();

  ArdroneLinkSettings ls = test::link_settings_for(emulator);
  ls.video_max_bitrate_kbps = 500;
  ArdroneLink link(ls, quiet());
  link.start();
  // navdata_demo, then video:bitrate_ctrl_mode, video:max_bitrate and video:bitrate, each acknowledged.
  REQUIRE(wait_until([&] { return emulator.video_bitrate_kbps() == 500; }, 10.0));
  REQUIRE(wait_until([&] { auto c = link.statistics().counters; return c.count("video_frames") && c.at("video_frames") > 20; }, 10.0));
  const double at_500 = bytes_per_frame(link, 1.5);
  link.set_config("video:max_bitrate", "3000");  // at run time, as a user's config would
  REQUIRE(wait_until([&] { return emulator.video_bitrate_kbps() == 3000; }, 10.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // rate control settles
  const double at_3000 = bytes_per_frame(link, 1.5);
  INFO("bytes per frame at 500 kbit/s " << at_500 << ", at 3000 kbit/s " << at_3000);
  CHECK(at_500 > 0);
  CHECK(at_500 < 500e3 / 8 / 30 * 2);  // ~2.1 kB per frame at 30 fps, IDRs included
  CHECK(at_3000 > 3.0 * at_500);
  // A value the firmware's range refuses leaves the rate as it was.
  link.set_config("video:max_bitrate", "90000");
  REQUIRE(wait_until([&] { return emulator.statistics().counters.count("config_bad_value") == 1; }, 10.0));
  CHECK(emulator.video_bitrate_kbps() == 3000);
  CHECK(emulator.statistics().counters.at("video_bitrate_changes") >= 2);  // 1000 -> 500 -> 3000
  link.stop();
  emulator.stop();
}

TEST_CASE("link: an emulator restarted over the same vehicle continues its time", "[link][loopback]") {
  test::TinyVehicle vehicle;
  vehicle.advance_to(100.0);  // the vehicle has run for 100 s under an emulator now gone
  ArdroneEmulatorSettings s;
  s.at_port = s.navdata_port = s.video_port = 0;
  ArdroneEmulator emulator(vehicle, s, quiet());
  CHECK(emulator.now() >= 100.0);
  emulator.start();
  // Its navdata thread drives the vehicle on its own clock: from 100 s on, not from 0.
  CHECK(wait_until([&] { return vehicle.now() > 100.2; }, 3.0));
  emulator.stop();
}

TEST_CASE("link: an emulator restarted under a flying vehicle lands it on the driver's land", "[link][loopback]") {
  // The flight software ended its mission during the restart and sends land (REF without the
  // take-off bit); the new emulator never saw the take-off, and must still land what flies.
  test::TinyVehicle vehicle;
  vehicle.start_flying(0.8);
  ArdroneEmulatorSettings s;
  s.at_port = s.navdata_port = s.video_port = 0;
  s.com_watchdog_s = 0.5;
  ArdroneEmulator emulator(vehicle, s, quiet());
  emulator.start();
  ArdroneLink link(test::link_settings_for(emulator), quiet());
  Recorder rec;
  link.set_listener(&rec);
  link.start();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  link.land();
  CHECK(wait_until([&] { return !vehicle.snapshot().flying; }, 5.0));
  CHECK(vehicle.snapshot().z_m == Approx(0.0).margin(0.01));
  link.stop();
  emulator.stop();
}
