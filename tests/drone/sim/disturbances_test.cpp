// Disturbances applied by SimulatedLab at their scheduled time: impulses along x, y, z and yaw (the
// paper's Figs 5-8), a wind gust, a video dropout, a lighting change; the teacher in the scene and as an obstacle; the
// ground-truth CSV.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include "drone/sim/ground_truth_log.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::sim;
using labo::test::ScratchDir;

namespace {

// Hovering at 1 m above the platform at t = 8 s, facing +x.
std::unique_ptr<SimulatedLab> hovering_lab(std::vector<Disturbance> disturbances, bool teacher = false) {
  SimulatedLabSettings s;
  s.teacher = teacher;
  s.disturbances = std::move(disturbances);
  auto v = std::make_unique<SimulatedLab>(test::shipped_lab(), s, std::make_unique<test::GreyRenderer>());
  v->takeoff(0.1);
  v->advance_to(8.0);
  REQUIRE(v->truth().phase == FirmwarePhase::Hovering);
  return v;
}

Disturbance impulse(Seconds t, Eigen::Vector3d dv, double dyaw_deg = 0) {
  Disturbance d;
  d.kind = Disturbance::Kind::Impulse;
  d.t_s = t;
  d.dv_heading_mps = dv;
  d.dyaw_rad = dyaw_deg * std::numbers::pi / 180;
  return d;
}

}  // namespace

TEST_CASE("sim disturbances: impulses along x, y, z at their time, in the drone's heading frame", "[sim][disturbances]") {
  auto v = hovering_lab({impulse(10.0, {0.8, 0, 0}), impulse(20.0, {0, -0.6, 0}), impulse(30.0, {0, 0, 0.5})});
  v->advance_to(9.99);
  CHECK(v->truth().velocity_mps.norm() < 0.05);
  v->advance_to(10.01);
  CHECK(v->truth().velocity_mps.x() == Approx(0.8).margin(0.05));
  v->advance_to(19.0);
  CHECK(v->truth().velocity_mps.norm() < 0.05);  // the firmware's hover brakes it
  const double x_after = v->truth().position_m.x();
  CHECK(x_after > 0.2);
  v->advance_to(20.01);
  CHECK(v->truth().velocity_mps.y() == Approx(-0.6).margin(0.05));
  v->advance_to(30.01);
  CHECK(v->truth().velocity_mps.z() == Approx(0.5).margin(0.05));
  v->advance_to(40.0);
  CHECK(v->truth().position_m.z() == Approx(1.1).margin(0.05));  // the height hold returns
}

TEST_CASE("sim disturbances: a yaw impulse turns the drone by about the given angle", "[sim][disturbances]") {
  auto v = hovering_lab({impulse(10.0, Eigen::Vector3d::Zero(), 20.0)});
  const double yaw0 = v->truth().yaw_rad;
  v->advance_to(11.0);
  CHECK((v->truth().yaw_rad - yaw0) * 180 / std::numbers::pi == Approx(20.0).margin(1.0));
  // In the heading frame: after the turn, a forward push moves along the new heading.
  v->schedule(impulse(12.0, {1.0, 0, 0}));
  v->advance_to(12.01);
  const double heading = std::atan2(v->truth().velocity_mps.y(), v->truth().velocity_mps.x());
  CHECK(heading == Approx(v->truth().yaw_rad).margin(0.02));
}

TEST_CASE("sim disturbances: a gust pushes the hovering drone downwind while it blows", "[sim][disturbances]") {
  Disturbance gust;
  gust.kind = Disturbance::Kind::Gust;
  gust.t_s = 10.0;
  gust.duration_s = 4.0;
  gust.wind_world_mps = {0.0, 2.0, 0.0};
  auto v = hovering_lab({gust});
  const double y0 = v->truth().position_m.y();
  v->advance_to(12.0);  // peak
  CHECK(v->truth().velocity_mps.y() > 0.2);
  v->advance_to(20.0);
  CHECK(v->truth().position_m.y() - y0 > 0.3);
  CHECK(v->truth().velocity_mps.norm() < 0.05);
}

TEST_CASE("sim disturbances: a video dropout leaves the camera image empty for its duration", "[sim][disturbances]") {
  Disturbance d;
  d.kind = Disturbance::Kind::VideoDropout;
  d.t_s = 9.0;
  d.duration_s = 0.5;
  auto v = hovering_lab({d});
  cv::Mat image;
  v->render(CameraId::Front, image);
  CHECK_FALSE(image.empty());
  v->advance_to(9.2);
  v->render(CameraId::Front, image);
  CHECK(image.empty());
  v->advance_to(9.6);
  v->render(CameraId::Front, image);
  CHECK_FALSE(image.empty());
}

TEST_CASE("sim disturbances: a lighting change raises the frames' exposure and lets it fall back", "[sim][disturbances]") {
  Disturbance d;
  d.kind = Disturbance::Kind::Lighting;
  d.t_s = 9.0;
  d.duration_s = 2.0;
  d.exposure_gain = 1.8;
  auto v = hovering_lab({d});
  CHECK(v->scene().exposure_gain == 1.0);
  v->advance_to(10.0);  // the middle of the change: its peak
  CHECK(v->scene().exposure_gain == Approx(1.8).margin(0.01));
  v->advance_to(11.5);
  CHECK(v->scene().exposure_gain == 1.0);

  // Two overlapping changes multiply: a lamp on while the sun comes out.
  DisturbanceSchedule schedule;
  Disturbance dim = d;
  dim.exposure_gain = 0.5;
  schedule.add(d);
  schedule.add(dim);
  CHECK(schedule.exposure_gain_at(10.0) == Approx(0.9));
  CHECK(schedule.exposure_gain_at(8.0) == 1.0);
}

TEST_CASE("sim teacher in the lab: walks in the scene and is an obstacle", "[sim][teacher]") {
  auto v = hovering_lab({}, true);
  const SceneState s = v->scene();
  CHECK(s.teacher_present);
  CHECK(s.T_world_head.translation().z() == Approx(test::shipped_lab().teacher.eye_height_m));
  // Fly the hovering drone into the walking teacher, steering towards where the teacher is now.
  for (Seconds t = 8.0; t < 20.0 && v->truth().crashes == 0; t += 0.03) {
    v->advance_to(t);
    const Eigen::Vector2d to = (v->scene().teacher_floor_xy - v->truth().position_m.head<2>()).normalized();
    const double yaw = v->truth().yaw_rad;
    // Pitch and roll towards the teacher in the heading frame.
    const double fwd = std::cos(yaw) * to.x() + std::sin(yaw) * to.y(), left = -std::sin(yaw) * to.x() + std::cos(yaw) * to.y();
    v->move({-0.4 * left, 0.4 * fwd, 0.0, 0.0}, false, t);
  }
  CHECK(v->truth().crash_reason == "teacher");
}

TEST_CASE("sim ground truth: the CSV holds a row per record and the lab's objects", "[sim][ground_truth]") {
  const ScratchDir scratch("sim_ground_truth");
  const auto dir = scratch / "logs";  // not there yet: the log creates it
  auto v = hovering_lab({}, true);
  {
    GroundTruthLog log(dir / "run.csv", test::shipped_lab());
    for (int i = 0; i < 10; ++i) {
      v->advance_to(8.0 + 0.1 * i);
      log.record(v->truth(), v->scene());
    }
    CHECK(log.rows() == 10);
  }
  std::ifstream in(dir / "run.csv");
  std::string header, row;
  std::getline(in, header);
  CHECK(header.rfind("t_s,x_m,y_m,z_m,yaw_rad", 0) == 0);
  int rows = 0;
  while (std::getline(in, row)) ++rows;
  CHECK(rows == 10);
  std::ifstream objects(dir / "run_objects.csv");
  int lines = 0;
  bool scope = false;
  while (std::getline(objects, row)) {
    ++lines;
    scope = scope || row.rfind("instrument,oscilloscope,5.85,-1.2,1,", 0) == 0;
  }
  CHECK(lines == 1 + static_cast<int>(test::shipped_lab().instruments.size() + 1 + test::shipped_lab().benches.size()));
  CHECK(scope);
  CHECK_THROWS_AS(GroundTruthLog("/proc/no/such/dir/run.csv", test::shipped_lab()), std::runtime_error);
}
