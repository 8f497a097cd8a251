// SimTelloLink: the simulated lab seen through what a Tello gives, in lockstep. Its rates, the state's
// resolution (whole degrees, dm/s, cm), the sticks, the downward camera, the flight phase from the
// commands, and the same flight bit for bit.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "drone/sim/sim_setup.hpp"
#include "drone/sim/sim_tello_link.hpp"
#include "drone/tello/tello_config.hpp"
#include "drone/tello/tello_flight_phase.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::tello;
using namespace labo::sim;

namespace {

struct Recorder final : DroneLinkListener {
  std::vector<NavdataSample> navdata;
  std::vector<VideoFrame> frames;  // without pixels
  std::vector<std::pair<LinkState, Seconds>> states;
  void on_navdata(const NavdataSample& s) override { navdata.push_back(s); }
  void on_video(const VideoFrame& f) override {
    frames.push_back(VideoFrame{f.t, f.camera, f.frame_number, {}});
    size = f.bgr.size();
  }
  void on_link_state(LinkState s, Seconds t) override { states.emplace_back(s, t); }
  cv::Size size;
};

struct Rig {
  std::unique_ptr<SimulatedLab> sim;
  std::unique_ptr<SimTelloLink> link;
  Recorder rec;
  // `rendered`: the lab's cameras with the Tello's in front; otherwise a grey picture.
  explicit Rig(SimLinkSettings ls = {}, std::uint64_t seed = 1, bool rendered = false) {
    SimulatedLabSettings s;
    s.seed = seed;
    const CamerasConfig cameras = tello_cameras(TelloConfig{}, test::stock_cameras());
    sim = rendered ? make_simulated_lab(test::shipped_lab(), cameras, s)
                   : std::make_unique<SimulatedLab>(test::shipped_lab(), s, std::make_unique<test::GreyRenderer>());
    ls.seed = seed;
    link = std::make_unique<SimTelloLink>(*sim, ls, sim_tello_settings(TelloConfig{}));
    link->set_listener(&rec);
  }
  // Drives the link at 50 Hz up to t.
  void run_to(Seconds t) {
    for (Seconds s = link->now(); s < t; s += 0.02) link->advance_to(std::min(s + 0.02, t));
  }
  // Takes off and waits until the link's flight phase says airborne.
  void take_off() {
    link->takeoff();
    const Seconds until = link->now() + 15.0;
    while (link->now() < until && (rec.navdata.empty() || rec.navdata.back().control_state != control_state::kHovering))
      run_to(link->now() + 0.1);
    REQUIRE(rec.navdata.back().control_state == control_state::kHovering);
  }
};

bool whole(double v, double unit) { return std::abs(v / unit - std::round(v / unit)) < 1e-9; }

}  // namespace

TEST_CASE("sim tello link: SDK mode first, then the state at 10 Hz and the front camera at 30 fps, delayed", "[sim][tello]") {
  SimLinkSettings ls;
  ls.jitter_s = 0;
  Rig rig(ls, 1, true);
  rig.run_to(10.0);
  // "command" and "streamon" each take a round trip before anything streams.
  REQUIRE_FALSE(rig.rec.navdata.empty());
  CHECK(rig.rec.navdata.front().t > ls.navdata_delay_s);
  CHECK(static_cast<double>(rig.rec.navdata.size()) == Approx(10 * 10).margin(2));
  // From the reply to "streamon" on (a few frames after t = 0), then 30 a second.
  CHECK(static_cast<double>(rig.rec.frames.size()) == Approx(30 * 10).margin(8));
  CHECK(rig.rec.size == cv::Size(960, 720));  // the Tello's camera (tello.camera)
  for (std::size_t i = 1; i < rig.rec.navdata.size(); ++i)
    CHECK(rig.rec.navdata[i].t - rig.rec.navdata[i - 1].t == Approx(0.1).margin(1e-9));
  CHECK_FALSE(rig.rec.navdata.back().has_drone_time);  // the state string has no clock
  CHECK(rig.rec.navdata.back().control_state == control_state::kLanded);
  REQUIRE_FALSE(rig.rec.states.empty());
  CHECK(rig.rec.states.back().first == LinkState::Connected);
  const LinkStatistics s = rig.link->statistics();
  CHECK(s.counters.at("tello_command_ok") == 2);  // command, streamon
  CHECK(s.counters.at("rc_sent") >= 190);         // every 50 ms once in SDK mode: the keep-alive
}

TEST_CASE("sim tello link: the state has the drone's resolution: whole degrees, dm/s, cm", "[sim][tello]") {
  Rig rig;
  rig.run_to(1.0);
  rig.take_off();
  // A slow forward and sideways drift with a turn: every value moves through many quanta.
  rig.link->move(MoveCommand{0.07, 0.11, 0.05, 0.2});
  const std::size_t from = rig.rec.navdata.size();
  rig.run_to(rig.link->now() + 4.0);
  const double degree = std::numbers::pi / 180.0;
  int moving = 0;
  for (std::size_t i = from; i < rig.rec.navdata.size(); ++i) {
    const NavdataSample& n = rig.rec.navdata[i];
    CHECK(whole(n.roll_rad, degree));
    CHECK(whole(n.pitch_rad, degree));
    CHECK(whole(n.yaw_rad, degree));
    CHECK(whole(n.vx_mps, 0.1));
    CHECK(whole(n.vy_mps, 0.1));
    CHECK(whole(n.vz_mps, 0.1));
    CHECK(whole(n.altitude_m, 0.01));
    moving += n.vx_mps > 0;
  }
  CHECK(moving > 10);  // forward stick: flies forward (LaboDrone's signs through the Tello's)
  CHECK(rig.rec.navdata.back().control_state == control_state::kFlying);
  // The sticks went out as whole percents and the drone flew them.
  CHECK(rig.link->drone_counters().get("rc_received") > 100);
  CHECK(rig.link->drone_counters().get("rc_malformed") == 0);
}

TEST_CASE("sim tello link: the bottom camera is the Tello EDU's downward one: downvision, grey 320x240 frames labelled Bottom", "[sim][tello]") {
  for (const bool h264 : {false, true}) {
    CAPTURE(h264);
    SimLinkSettings ls;
    ls.h264 = h264;
    Rig rig(ls, 1, true);
    rig.run_to(1.0);
    rig.link->select_camera(CameraId::Bottom);
    rig.run_to(2.0);
    REQUIRE_FALSE(rig.rec.frames.empty());
    CHECK(rig.rec.frames.back().camera == CameraId::Bottom);
    CHECK(rig.rec.size == cv::Size(320, 240));
    rig.link->select_camera(CameraId::Front);
    rig.run_to(3.0);
    CHECK(rig.rec.frames.back().camera == CameraId::Front);
    CHECK(rig.rec.size == cv::Size(960, 720));
    // Labels follow the pictures: no frame of one camera's size carries the other's label.
    const LinkStatistics s = rig.link->statistics();
    CHECK(s.counters.count("tello_bottom_camera_unavailable") == 0);
    CHECK(rig.link->drone_counters().get("downvision_on") == 1);
    CHECK(rig.link->drone_counters().get("downvision_off") == 1);
  }
}

TEST_CASE("sim tello link: a Tello without the downward camera refuses it: counted, every frame stays Front", "[sim][tello]") {
  SimLinkSettings ls;
  SimulatedLabSettings labs;
  labs.seed = 1;
  SimulatedLab lab(test::shipped_lab(), labs, std::make_unique<test::GreyRenderer>());
  SimTelloSettings ts = sim_tello_settings(TelloConfig{});
  ts.firmware.downvision = false;  // a plain Tello answers "error"
  SimTelloLink link(lab, ls, ts);
  Recorder rec;
  link.set_listener(&rec);
  for (Seconds t = 0.02; t <= 1.0; t += 0.02) link.advance_to(t);
  link.select_camera(CameraId::Bottom);
  link.flat_trim();
  for (Seconds t = 1.02; t <= 4.0; t += 0.02) link.advance_to(t);
  link.select_camera(CameraId::Bottom);  // the link knows now: refused without asking the drone again
  for (Seconds t = 4.02; t <= 5.0; t += 0.02) link.advance_to(t);
  REQUIRE_FALSE(rec.frames.empty());
  CHECK(std::all_of(rec.frames.begin(), rec.frames.end(), [](const VideoFrame& f) { return f.camera == CameraId::Front; }));
  const LinkStatistics s = link.statistics();
  CHECK(s.counters.at("tello_downvision_refused") == 1);
  CHECK(s.counters.at("tello_bottom_camera_unavailable") == 1);
  CHECK(s.counters.at("tello_flat_trim_not_in_sdk") == 1);
  CHECK(link.drone_counters().get("downvision_unsupported") == 1);
  CHECK_THROWS_AS(link.set_config("video:video_channel", "1"), std::invalid_argument);
}

TEST_CASE("sim tello link: video_fps counts the frames the link decoded, with H.264 as without", "[sim][tello]") {
  for (const bool h264 : {false, true}) {
    CAPTURE(h264);
    SimLinkSettings ls;
    ls.h264 = h264;
    Rig rig(ls, 1, true);
    rig.run_to(10.0);
    const LinkStatistics s = rig.link->statistics();
    // 30 fps from the reply to "streamon" on (a few frames after t = 0), over the 10 s.
    CHECK(s.video_fps == Approx(static_cast<double>(rig.rec.frames.size()) / 10.0).margin(1e-9));
    CHECK(s.video_fps == Approx(30.0).margin(1.0));
  }
}

TEST_CASE("sim tello link: take-off, landing and the flight phase from the replies", "[sim][tello]") {
  Rig rig;
  rig.run_to(1.0);
  rig.take_off();
  CHECK(rig.sim->truth().position_m.z() > 0.5);
  rig.link->land();
  rig.run_to(rig.link->now() + 10.0);
  CHECK(rig.rec.navdata.back().control_state == control_state::kLanded);
  CHECK(rig.sim->truth().position_m.z() < 0.3);
  CHECK(rig.link->statistics().counters.at("tello_command_ok") == 4);  // command, streamon, takeoff, land
}

TEST_CASE("sim tello link: a silent drone is Lost and SDK mode is entered again", "[sim][tello]") {
  SimLinkSettings ls;
  ls.jitter_s = 0;
  Rig rig(ls);
  rig.run_to(2.0);
  Disturbance outage;
  outage.kind = Disturbance::Kind::LinkOutage;
  outage.t_s = 3.0;
  outage.duration_s = 3.0;
  rig.sim->schedule(outage);
  rig.run_to(10.0);
  std::vector<LinkState> seen;
  for (const auto& [s, t] : rig.rec.states) seen.push_back(s);
  CHECK(std::find(seen.begin(), seen.end(), LinkState::Lost) != seen.end());
  CHECK(seen.back() == LinkState::Connected);
  CHECK(rig.link->statistics().counters.at("reconnects") == 1);
}

TEST_CASE("sim tello link: the same seeds give the same flight bit for bit", "[sim][tello]") {
  SimLinkSettings ls;
  ls.navdata_loss = 0.05;
  ls.command_loss = 0.05;
  ls.video_loss = 0.05;
  auto fly = [&](std::uint64_t seed) {
    Rig rig(ls, seed);
    rig.run_to(1.0);
    rig.link->takeoff();
    rig.run_to(8.0);
    rig.link->move(MoveCommand{0.1, -0.2, 0.1, 0.3});
    rig.run_to(11.0);
    std::vector<double> trace;
    for (const NavdataSample& n : rig.rec.navdata)
      trace.insert(trace.end(), {n.t, n.roll_rad, n.pitch_rad, n.yaw_rad, n.vx_mps, n.altitude_m, double(n.control_state)});
    for (const VideoFrame& f : rig.rec.frames) trace.push_back(f.t);
    trace.push_back(rig.sim->truth().position_m.x());
    return trace;
  };
  const std::vector<double> a = fly(7), b = fly(7), c = fly(8);
  CHECK(a == b);
  CHECK(a != c);
}
