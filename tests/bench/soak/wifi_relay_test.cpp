// The soak's stand-in for the Wi-Fi (bench/soak/wifi_relay.hpp) between the real driver and the
// emulator: it carries the whole protocol, and a cut loses every datagram both ways.
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "bench/soak/wifi_relay.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"

using namespace labo;
using namespace labo::ardrone2;
using namespace labo::bench;

namespace {

template <typename Pred>
bool wait_until(Pred pred, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

struct Frames final : DroneLinkListener {
  std::atomic<int> frames{0};
  void on_navdata(const NavdataSample&) override {}
  void on_video(const VideoFrame&) override { ++frames; }
  void on_link_state(LinkState, Seconds) override {}
};

struct Flight {
  test::TinyVehicle vehicle;
  ArdroneEmulator emulator{vehicle, [] {
                             ArdroneEmulatorSettings s;
                             s.at_port = s.navdata_port = s.video_port = 0;
                             s.com_watchdog_s = 0.5;
                             return s;
                           }(),
                           Logger("test", LogLevel::Off)};
  std::unique_ptr<WifiRelay> relay;
  std::unique_ptr<ArdroneLink> link;
  Frames listener;

  Flight() {
    emulator.start();
    relay = std::make_unique<WifiRelay>(emulator.at_port(), emulator.navdata_port(), emulator.video_port());
    ArdroneLinkSettings ls;
    ls.host = "127.0.0.1";
    ls.at_port = relay->at_port();
    ls.navdata_port = relay->navdata_port();
    ls.video_port = relay->video_port();
    ls.lost_after_s = 1.0;
    link = std::make_unique<ArdroneLink>(ls, Logger("test", LogLevel::Off));
    link->set_listener(&listener);
    link->start();
  }
  ~Flight() {
    link->stop();
    relay.reset();
    emulator.stop();
  }
};

}  // namespace

TEST_CASE("wifi relay: the driver flies a vehicle and watches its video through it", "[soak]") {
  Flight f;
  REQUIRE(wait_until([&] { return f.link->state() == LinkState::Connected; }, 5.0));
  f.link->takeoff();
  CHECK(wait_until([&] { return f.vehicle.snapshot().flying; }, 5.0));
  CHECK(wait_until([&] { return f.listener.frames > 5; }, 5.0));
  CHECK(f.relay->video_connections() >= 1);
  CHECK(f.relay->datagrams_lost() == 0);
}

TEST_CASE("wifi relay: after a cut the link is lost, then the driver's commands reach the drone again",
          "[soak]") {
  Flight f;
  REQUIRE(wait_until([&] { return f.link->state() == LinkState::Connected; }, 5.0));
  f.link->takeoff();
  REQUIRE(wait_until([&] { return f.vehicle.snapshot().flying; }, 5.0));
  // Long enough that the drone's last sequence number is far beyond what the driver sends after
  // its reset before the cut ends.
  std::this_thread::sleep_for(std::chrono::seconds(6));
  f.relay->cut_for(2.5);
  CHECK(wait_until([&] { return f.link->state() == LinkState::Lost; }, 3.0));
  CHECK(f.relay->datagrams_lost() > 10);
  REQUIRE(wait_until([&] { return f.link->state() == LinkState::Connected; }, 8.0));
  // The driver restarted its AT sequence at 1 while the cut lost those datagrams: the drone must
  // take its commands again all the same.
  f.link->move(MoveCommand{0.0, 0.3, 0.0, 0.0});
  CHECK(wait_until([&] { return f.vehicle.snapshot().last_move.pitch > 0.2; }, 3.0));
  const int frames = f.listener.frames;
  CHECK(wait_until([&] { return f.listener.frames > frames + 5; }, 8.0));  // video reconnected
}
