// One conformance suite for every DroneLink: what the flight software relies on, checked on the
// events a link delivers, whatever drone is behind it. Each live link flies the same script against
// its emulator over loopback (a tiny vehicle inside), recording the flight; the replay link then plays
// that recording, and the same checks run on its events:
//   connect (Connecting, then Connected, navdata with its time, landed),
//   take-off (6 then hovering, altitude up), move (each axis in LaboDrone's signs), land (8 then 2),
//   emergency (landed at once), video (frames with increasing times and numbers, one camera, one size),
//   link loss and recovery (Degraded, Lost, Connected again, navdata again),
//   bad packets (junk on the telemetry port, and on the video port where it is UDP: counted, the link
//   stays up).
#include <catch2/catch.hpp>
#include <algorithm>
#include <filesystem>
#include <memory>
#include <mutex>
#include <thread>
#include <unistd.h>
#include <vector>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/replay/replay_link.hpp"
#include "drone/tello/tello_emulator.hpp"
#include "drone/tello/tello_link.hpp"
#include "tests/drone/ardrone2/tiny_vehicle.hpp"
#include "tests/drone/link_events.hpp"
#include "tests/drone/sim/loopback_support.hpp"

using namespace labo;
using namespace labo::ardrone2;
using namespace labo::replay;
using namespace labo::tello;

namespace {

Logger quiet() { return Logger("test", LogLevel::Off); }

using FlightLog = test::LinkEvents;

std::uint64_t count(const LinkStatistics& s, const std::string& kind) {
  const auto it = s.counters.find(kind);
  return it == s.counters.end() ? 0 : it->second;
}

// A live link and the emulator it talks to, behind one interface for the script.
class LiveSubject {
 public:
  virtual ~LiveSubject() = default;
  virtual DroneLink& link() = 0;
  virtual void start() = 0;
  virtual void stop() = 0;
  virtual void drone_goes_away() = 0;
  virtual void drone_comes_back() = 0;
  // Junk datagrams to the link's telemetry port (and to its video port where that is UDP).
  virtual void send_junk() = 0;
  virtual bool video_over_udp() const = 0;
  // The counters that say the junk was seen.
  virtual std::vector<std::string> telemetry_junk_kinds() const = 0;
  test::TinyVehicle vehicle;
};

void send_datagrams(int port, std::span<const std::uint8_t> bytes, int times) {
  ardrone2::Socket junk = ardrone2::Socket::udp(0, "127.0.0.1");
  const auto to = ardrone2::Endpoint::resolve("127.0.0.1", port);
  for (int i = 0; i < times; ++i) junk.send_to(bytes, to);
}

class ArdroneSubject final : public LiveSubject {
 public:
  explicit ArdroneSubject(const std::filesystem::path& recording) {
    es_.at_port = es_.navdata_port = es_.video_port = 0;
    es_.com_watchdog_s = 0.5;  // a loaded machine delays the AT loop: keep the watchdog bit quiet
    emulator_ = std::make_unique<ArdroneEmulator>(vehicle, es_, quiet());
    emulator_->start();
    ArdroneLinkSettings ls = test::link_settings_for(*emulator_);
    ls.degraded_after_s = 0.3;
    ls.lost_after_s = 0.8;
    ls.recording = recording;
    es_.at_port = ls.at_port;  // the drone comes back on the same ports
    es_.navdata_port = ls.navdata_port;
    es_.video_port = ls.video_port;
    link_ = std::make_unique<ArdroneLink>(ls, quiet());
  }
  DroneLink& link() override { return *link_; }
  void start() override { link_->start(); }
  void stop() override {
    link_->stop();
    emulator_.reset();
  }
  void drone_goes_away() override { emulator_.reset(); }
  void drone_comes_back() override {
    emulator_ = std::make_unique<ArdroneEmulator>(vehicle, es_, quiet());
    emulator_->start();
  }
  void send_junk() override {
    const std::vector<std::uint8_t> junk = {0x88, 0x77, 0x66, 0x55, 1, 2, 3};  // a navdata magic, then nothing
    send_datagrams(link_->navdata_local_port(), junk, 10);
  }
  bool video_over_udp() const override { return false; }  // TCP from the emulator: no one else's bytes
  std::vector<std::string> telemetry_junk_kinds() const override { return {"navdata_truncated"}; }

 private:
  ArdroneEmulatorSettings es_;
  std::unique_ptr<ArdroneEmulator> emulator_;
  std::unique_ptr<ArdroneLink> link_;
};

class TelloSubject final : public LiveSubject {
 public:
  explicit TelloSubject(const std::filesystem::path& recording) {
    es_.command_port = 0;
    es_.video_width = 480;
    es_.video_height = 360;
    emulator_ = std::make_unique<TelloEmulator>(vehicle, es_, quiet());
    emulator_->start();
    TelloLinkSettings ls;
    ls.host = "127.0.0.1";
    ls.command_port = emulator_->command_port();
    ls.state_port = ls.video_port = 0;
    ls.degraded_after_s = 0.3;
    ls.lost_after_s = 0.8;
    ls.reply_timeout_s = 0.2;
    ls.recording = recording;
    link_ = std::make_unique<TelloLink>(ls, quiet());
    link_->open();
    es_.command_port = ls.command_port;  // the drone comes back on the same ports
    es_.client_state_port = link_->state_port();
    es_.client_video_port = link_->video_port();
    emulator_->set_client_ports(es_.client_state_port, es_.client_video_port);
  }
  DroneLink& link() override { return *link_; }
  void start() override { link_->start(); }
  void stop() override {
    link_->stop();
    emulator_.reset();
  }
  void drone_goes_away() override { emulator_.reset(); }
  void drone_comes_back() override {
    emulator_ = std::make_unique<TelloEmulator>(vehicle, es_, quiet());
    emulator_->start();
  }
  void send_junk() override {
    const std::string state = "pitch:0;roll:0;yaw:x;";
    send_datagrams(link_->state_port(), std::span(reinterpret_cast<const std::uint8_t*>(state.data()), state.size()), 10);
    const std::vector<std::uint8_t> video = {0xde, 0xad, 0xbe, 0xef, 0x42};  // no start code
    send_datagrams(link_->video_port(), video, 10);
  }
  bool video_over_udp() const override { return true; }
  std::vector<std::string> telemetry_junk_kinds() const override { return {"tello_state_bad_number"}; }

 private:
  TelloEmulatorSettings es_;
  std::unique_ptr<TelloEmulator> emulator_;
  std::unique_ptr<TelloLink> link_;
};

// The script every live link flies. Each step waits for the link to report what it asked for.
void fly_script(LiveSubject& subject, FlightLog& log) {
  DroneLink& link = subject.link();
  link.set_listener(&log);
  subject.start();
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 10.0));
  REQUIRE(test::eventually([&] { std::lock_guard l(log.m); return log.frames.size() >= 5; }, 10.0));

  subject.send_junk();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));

  subject.drone_goes_away();
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Lost; }, 5.0));
  subject.drone_comes_back();
  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 10.0));

  link.takeoff();
  REQUIRE(test::eventually([&] { const auto n = log.last(); return n.control_state == 4 && n.altitude_m > 0.6; }, 10.0));
  link.move(MoveCommand{0.0, 0.5, 0.0, 0.0});
  REQUIRE(test::eventually([&] { return log.last().vx_mps > 0.3; }, 5.0));
  link.move(MoveCommand{-0.5, 0.0, 0.0, 0.0});
  REQUIRE(test::eventually([&] { return log.last().vy_mps > 0.3; }, 5.0));
  const double yaw_before = log.last().yaw_rad;
  link.move(MoveCommand{0.0, 0.0, 0.0, 0.5});
  REQUIRE(test::eventually([&] { return log.last().yaw_rad > yaw_before + 0.2; }, 5.0));
  link.hover();
  REQUIRE(test::eventually([&] { return log.last().control_state == 4; }, 5.0));
  link.land();
  REQUIRE(test::eventually([&] { const auto n = log.last(); return n.control_state == 2 && n.altitude_m < 0.05; }, 10.0));

  link.takeoff();
  REQUIRE(test::eventually([&] { return log.last().control_state == 4; }, 10.0));
  link.emergency();
  REQUIRE(test::eventually([&] { const auto n = log.last(); return n.control_state == 2 && n.altitude_m < 0.05; }, 5.0));
  subject.stop();
}

// Indices of the first samples, in order, whose control_state is each of `phases` in turn.
bool passes_through(const std::vector<NavdataSample>& navdata, const std::vector<int>& phases) {
  std::size_t next = 0;
  for (const auto& n : navdata)
    if (next < phases.size() && n.control_state == phases[next]) ++next;
  return next == phases.size();
}

bool states_in_order(const std::vector<std::pair<LinkState, Seconds>>& states, const std::vector<LinkState>& order) {
  std::size_t next = 0;
  for (const auto& [s, t] : states)
    if (next < order.size() && s == order[next]) ++next;
  return next == order.size();
}

// The checks, on what a link delivered (live or replayed).
void check_conformance(FlightLog& log, const LinkStatistics& stats, const LiveSubject& subject) {
  std::lock_guard l(log.m);
  // Connect, loss and recovery.
  CHECK(states_in_order(log.states, {LinkState::Connecting, LinkState::Connected, LinkState::Degraded,
                                     LinkState::Lost, LinkState::Connected}));
  for (std::size_t i = 1; i < log.states.size(); ++i) CHECK(log.states[i].second >= log.states[i - 1].second);
  // Navdata: times on the link's clock, never backwards; landed first, a battery.
  REQUIRE(log.navdata.size() > 20);
  CHECK(log.navdata.front().control_state == 2);
  CHECK(log.navdata.front().battery_percent > 0);
  for (std::size_t i = 1; i < log.navdata.size(); ++i) CHECK(log.navdata[i].t >= log.navdata[i - 1].t);
  // Take-off, flight, landing, take-off, emergency.
  CHECK(passes_through(log.navdata, {2, 6, 4, 3, 4, 8, 2, 6, 4, 2}));
  // Each axis in LaboDrone's signs while flying.
  auto any = [&](auto pred) { return std::any_of(log.navdata.begin(), log.navdata.end(), pred); };
  CHECK(any([](const NavdataSample& n) { return n.control_state == 3 && n.vx_mps > 0.3; }));   // forward
  CHECK(any([](const NavdataSample& n) { return n.control_state == 3 && n.vy_mps > 0.3; }));   // left
  CHECK(any([](const NavdataSample& n) { return n.altitude_m > 0.6; }));
  CHECK(log.navdata.back().altitude_m < 0.05);
  // Video: frames with times and numbers that go forward, one camera, one size, within the flight.
  REQUIRE(log.frames.size() > 20);
  for (std::size_t i = 1; i < log.frames.size(); ++i) {
    INFO("frame " << i);
    CHECK(log.frames[i].t >= log.frames[i - 1].t);
    CHECK(log.frames[i].camera == CameraId::Front);
    CHECK(log.frames[i].width == log.frames[0].width);
    CHECK(log.frames[i].height == log.frames[0].height);
  }
  std::size_t increasing = 0;
  for (std::size_t i = 1; i < log.frames.size(); ++i) increasing += log.frames[i].number > log.frames[i - 1].number;
  CHECK(increasing + 3 >= log.frames.size());  // numbering restarts at most with each new stream
  CHECK(log.frames.front().t >= log.navdata.front().t - 1.0);
  CHECK(log.frames.back().t <= log.navdata.back().t + 1.0);
  // Bad packets: counted; the link did not drop (Lost comes once, when the drone went away).
  for (const auto& kind : subject.telemetry_junk_kinds()) CHECK(count(stats, kind) >= 10);
  if (subject.video_over_udp()) CHECK(count(stats, "tello_video_junk") >= 1);
  CHECK(std::count_if(log.states.begin(), log.states.end(), [](const auto& s) { return s.first == LinkState::Lost; }) == 1);
}

std::filesystem::path temp_recording(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".laborec");
}

template <typename Subject>
void live_then_replay(const std::string& name) {
  const auto recording = temp_recording(name);
  FlightLog live;
  LinkStatistics live_stats;
  {
    Subject subject(recording);
    fly_script(subject, live);
    live_stats = subject.link().statistics();
    {
      INFO("the live link");
      check_conformance(live, live_stats, subject);
    }
    {
      INFO("the replay link, playing the live link's recording");
      FlightLog replayed;
      ReplayLink replay(recording, quiet());
      replay.set_listener(&replayed);
      replay.run_to_end();
      CHECK_FALSE(replay.truncated());
      check_conformance(replayed, replay.statistics(), subject);
    }
  }
  std::filesystem::remove(recording);
}

}  // namespace

TEST_CASE("link conformance: the AR.Drone link and the replay of its recording", "[conformance][loopback]") {
  live_then_replay<ArdroneSubject>("conformance_ardrone");
}

TEST_CASE("link conformance: the Tello link and the replay of its recording", "[conformance][loopback]") {
  live_then_replay<TelloSubject>("conformance_tello");
}
