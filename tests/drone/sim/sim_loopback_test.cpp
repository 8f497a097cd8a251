// The project's own AR.Drone 2.0 driver flies the simulated lab through the protocol emulator on
// loopback (ephemeral ports): handshake, take-off to about 1 m, a move, decoded video, landing.
#include <catch2/catch.hpp>

#include <mutex>
#include <vector>

#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/ardrone2/ardrone_link.hpp"
#include "drone/sim/sim_setup.hpp"
#include "tests/drone/sim/loopback_support.hpp"

using namespace labo;
using namespace labo::ardrone2;
using namespace labo::lab;
using namespace labo::sim;

namespace {

// The emulator serialises its calls; the test reads the truth from its own thread, so every call
// goes through one more lock.
class LockedVehicle final : public EmulatedVehicle {
 public:
  explicit LockedVehicle(SimulatedLab& lab) : lab_(lab) {}
  void takeoff(Seconds t) override { std::lock_guard l(m_); lab_.takeoff(t); }
  void land(Seconds t) override { std::lock_guard l(m_); lab_.land(t); }
  void emergency(Seconds t) override { std::lock_guard l(m_); lab_.emergency(t); }
  void flat_trim(Seconds t) override { std::lock_guard l(m_); lab_.flat_trim(t); }
  void move(const MoveCommand& c, bool hover, Seconds t) override { std::lock_guard l(m_); lab_.move(c, hover, t); }
  void select_camera(CameraId c, Seconds t) override { std::lock_guard l(m_); lab_.select_camera(c, t); }
  void advance_to(Seconds t) override { std::lock_guard l(m_); lab_.advance_to(t); }
  Seconds now() const override { std::lock_guard l(m_); return lab_.now(); }
  VehicleTelemetry telemetry() const override { std::lock_guard l(m_); return lab_.telemetry(); }
  CameraId selected_camera() const override { std::lock_guard l(m_); return lab_.selected_camera(); }
  void render(CameraId c, cv::Mat& bgr) override { std::lock_guard l(m_); lab_.render(c, bgr); }
  QuadrotorState truth() const { std::lock_guard l(m_); return lab_.truth(); }

 private:
  mutable std::mutex m_;
  SimulatedLab& lab_;
};

struct Recorder : DroneLinkListener {
  std::mutex m;
  NavdataSample last_nav;
  int navdata = 0;
  int frames = 0;
  cv::Mat last_frame;
  void on_navdata(const NavdataSample& s) override {
    std::lock_guard l(m);
    last_nav = s;
    ++navdata;
  }
  void on_video(const VideoFrame& f) override {
    std::lock_guard l(m);
    f.bgr.copyTo(last_frame);
    ++frames;
  }
  void on_link_state(LinkState, Seconds) override {}
  NavdataSample nav() {
    std::lock_guard l(m);
    return last_nav;
  }
};

}  // namespace

TEST_CASE("sim loopback: ArdroneLink takes off, flies, streams and lands the simulated lab through the emulator", "[sim][loopback]") {
  const LabDescription lab = load_lab_description(default_lab_path());
  auto sim = make_simulated_lab(lab, ardrone2_cameras(),
                                SimulatedLabSettings{});
  LockedVehicle vehicle(*sim);
  ArdroneEmulatorSettings es;
  es.at_port = es.navdata_port = es.video_port = 0;
  es.com_watchdog_s = 0.5;  // a loaded 2-core machine: keep the watchdog bit quiet
  const Logger quiet("test", LogLevel::Off);
  ArdroneEmulator emulator(vehicle, es, quiet);
  emulator.start();
  ArdroneLink link(test::link_settings_for(emulator), quiet);
  Recorder rec;
  link.set_listener(&rec);
  link.start();

  REQUIRE(test::eventually([&] { return link.state() == LinkState::Connected; }, 5.0));
  REQUIRE(test::eventually([&] { return rec.nav().state & (1u << 10); }, 5.0));  // navdata_demo acknowledged
  CHECK(rec.nav().control_state == 2);
  CHECK(rec.nav().battery_percent > 90);

  link.flat_trim();
  link.takeoff();
  REQUIRE(test::eventually([&] { return rec.nav().control_state == 4; }, 10.0));
  CHECK(rec.nav().altitude_m == Approx(1.0).margin(0.12));
  CHECK(vehicle.truth().position_m.z() - 0.10 == Approx(1.0).margin(0.1));

  // Forward for a second: the true drone moves along +x and the navdata reports it.
  const double x0 = vehicle.truth().position_m.x();
  link.move({0.0, 0.4, 0.0, 0.0});
  REQUIRE(test::eventually([&] { return vehicle.truth().position_m.x() > x0 + 0.3; }, 5.0));
  CHECK(rec.nav().control_state == 3);
  CHECK(rec.nav().vx_mps > 0.2);
  CHECK(rec.nav().pitch_rad > 0.02);
  link.hover();
  REQUIRE(test::eventually([&] { return vehicle.truth().velocity_mps.norm() < 0.1; }, 5.0));

  // Video: decoded 640x360 frames of the lab, not a flat picture.
  REQUIRE(test::eventually([&] { std::lock_guard l(rec.m); return rec.frames >= 10; }, 10.0));
  {
    std::lock_guard l(rec.m);
    CHECK(rec.last_frame.size() == cv::Size(640, 360));
    cv::Scalar mean, stddev;
    cv::meanStdDev(rec.last_frame, mean, stddev);
    CHECK(stddev[0] > 10);
  }

  link.land();
  REQUIRE(test::eventually([&] { return rec.nav().control_state == 2; }, 10.0));
  CHECK(rec.nav().altitude_m == 0.0);
  CHECK(vehicle.truth().phase == FirmwarePhase::Landed);
  CHECK(vehicle.truth().crashes == 0);
  CHECK(link.statistics().counters.count("navdata_bad_checksum") == 0);
  link.stop();
  emulator.stop();
}
