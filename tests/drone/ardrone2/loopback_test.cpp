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
#include "tests/drone/ardrone2/tiny_vehicle.hpp"

using namespace labo;

namespace {

struct Recorder : DroneLinkListener {
  std::mutex m;
  std::vector<NavdataSample> navdata;
  std::vector<VideoFrame> frames;
  std::vector<LinkState> states;
  void on_navdata(const NavdataSample& s) override {
    std::lock_guard l(m);
    navdata.push_back(s);
  }
  void on_video(const VideoFrame& f) override {
    std::lock_guard l(m);
    VideoFrame copy = f;
    copy.bgr = f.bgr.clone();
    frames.push_back(copy);
  }
  void on_link_state(LinkState s, Seconds) override {
    std::lock_guard l(m);
    states.push_back(s);
  }
  NavdataSample last() {
    std::lock_guard l(m);
    return navdata.empty() ? NavdataSample{} : navdata.back();
  }
};

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
  es.com_watchdog_s = 0.5;  // the 2-core CI machine is loaded: keep the watchdog bit quiet
  ArdroneEmulator emulator(vehicle, es, quiet());
  emulator.start();

  ArdroneLinkSettings ls;
  ls.host = "127.0.0.1";
  ls.at_port = emulator.at_port();
  ls.navdata_port = emulator.navdata_port();
  ls.video_port = emulator.video_port();
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
    CHECK(f.bgr.cols == 640);
    CHECK(f.bgr.rows == 360);
    CHECK(f.camera == CameraId::Front);
    CHECK(cv::mean(f.bgr)[2] > 150);  // the front view is red
  }
  link.select_camera(CameraId::Bottom);
  REQUIRE(wait_until([&] {
    std::lock_guard l(rec.m);
    const auto& f = rec.frames.back();
    return f.camera == CameraId::Bottom && cv::mean(f.bgr)[1] > 150;  // the bottom view is green
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
  CHECK(rec.states.front() == LinkState::Connecting);
  CHECK(rec.states.back() == LinkState::Disconnected);
}

TEST_CASE("link: supervision marks the link degraded, lost, and reconnects", "[link][loopback]") {
  test::TinyVehicle vehicle;
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.5;
  auto emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  ArdroneLinkSettings ls;
  ls.host = "127.0.0.1";
  ls.at_port = emulator->at_port();
  ls.navdata_port = emulator->navdata_port();
  ls.video_port = emulator->video_port();
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
  {
    std::lock_guard l(rec.m);
    CHECK(std::find(rec.states.begin(), rec.states.end(), LinkState::Degraded) != rec.states.end());
  }
  // ...and comes back on the same ports: the link reconnects without a restart.
  emulator = std::make_unique<ArdroneEmulator>(vehicle, es, quiet());
  emulator->start();
  REQUIRE(wait_until([&] { return link.state() == LinkState::Connected; }, 5.0));
  REQUIRE(wait_until([&] { return (rec.last().state & (1u << 11)) == 0; }, 5.0));  // config sent again
  CHECK(link.statistics().counters.at("reconnects") == 1);
  link.stop();
}
