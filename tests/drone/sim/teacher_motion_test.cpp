// TeacherMotion: the walk along the waypoints at speed with pauses, the loop, and the head's pose in
// the CANDIDE-3 face frame.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "drone/sim/teacher_motion.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;

namespace {

TeacherSpec square_walk() {
  TeacherSpec s;
  s.waypoints = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 1.0}};
  s.speed_mps = 0.5;
  s.pause_s = 2.0;
  s.eye_height_m = 1.6;
  s.head = {0, 7, 0, 5, 0, 9};  // no head motion
  return s;
}

}  // namespace

TEST_CASE("sim teacher: pauses at each waypoint, walks at speed, loops", "[sim][teacher]") {
  const TeacherMotion m(square_walk());
  // Legs: pause 2 s, walk 2 m (4 s), pause, walk 1 m (2 s), pause, walk back sqrt(5) m.
  CHECK(m.cycle_s() == Approx(3 * 2.0 + (2.0 + 1.0 + std::sqrt(5.0)) / 0.5));
  CHECK(m.pose(1.0).floor_xy.isApprox(Eigen::Vector2d(0.0, 0.0)));
  CHECK_FALSE(m.pose(1.0).walking);
  const TeacherPose walking = m.pose(2.0 + 3.0);
  CHECK(walking.walking);
  CHECK(walking.floor_xy.x() == Approx(1.5));
  CHECK(walking.heading_rad == Approx(0.0).margin(1e-12));
  CHECK(m.pose(6.0 + 2.0 + 1.0).floor_xy.isApprox(Eigen::Vector2d(2.0, 0.5)));
  CHECK(m.pose(6.0 + 2.0 + 1.0).heading_rad == Approx(std::numbers::pi / 2));
  // One cycle later: the same pose.
  CHECK(m.pose(5.0 + m.cycle_s()).floor_xy.isApprox(walking.floor_xy, 1e-9));
  // During a pause the teacher turns smoothly from the incoming to the outgoing direction.
  const double mid_turn = m.pose(6.0 + 1.0).heading_rad;
  CHECK(mid_turn == Approx(std::numbers::pi / 4).margin(1e-9));
}

TEST_CASE("sim teacher: the head is at eye height, in the face frame, turning relative to the walk", "[sim][teacher]") {
  TeacherSpec spec = square_walk();
  const TeacherMotion still(spec);
  const TeacherPose p = still.pose(5.0);  // walking along +x
  CHECK(p.T_world_head.translation().isApprox(Eigen::Vector3d(1.5, 0.0, 1.6)));
  const Eigen::Matrix3d R = p.T_world_head.linear();
  CHECK((R.transpose() * R).isApprox(Eigen::Matrix3d::Identity()));
  CHECK(R.determinant() == Approx(1.0));
  CHECK(R.col(2).isApprox(Eigen::Vector3d::UnitX()));  // +z out of the face: forward
  CHECK(R.col(1).isApprox(Eigen::Vector3d::UnitZ()));  // +y up
  CHECK(R.col(0).isApprox(Eigen::Vector3d::UnitY()));  // +x the subject's left

  spec.head = {30, 8, 0, 5, 0, 9};  // yaw only: ±30 deg over 8 s
  const TeacherMotion turning(spec);
  const Eigen::Matrix3d Rt = turning.pose(2.0 + 2.0).T_world_head.linear();  // sin(2π·4/8) = 0 ...
  CHECK(Rt.col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  const Eigen::Matrix3d Rl = turning.pose(2.0).T_world_head.linear();  // ... sin(2π·2/8) = 1: 30 deg to the left
  CHECK(std::atan2(Rl(1, 2), Rl(0, 2)) == Approx(30.0 * std::numbers::pi / 180));
  CHECK(Rl.col(1).isApprox(Eigen::Vector3d::UnitZ()));  // a turn keeps the head upright
}

TEST_CASE("sim teacher: a path without waypoints or speed is refused", "[sim][teacher]") {
  TeacherSpec s = square_walk();
  s.speed_mps = 0;
  CHECK_THROWS_AS(TeacherMotion(s), std::invalid_argument);
  s = square_walk();
  s.waypoints.clear();
  CHECK_THROWS_AS(TeacherMotion(s), std::invalid_argument);
}

TEST_CASE("sim teacher: a drawn walk pauses its own time at each waypoint and ends standing at the last", "[sim][teacher]") {
  TeacherSpec s = square_walk();
  s.loop = false;
  s.pauses_s = {1.0, 0.5, 4.0};
  const TeacherMotion m(s);
  // Pause 1 s, walk 2 m (4 s), pause 0.5 s, walk 1 m (2 s), then stand at (2, 1) for ever (the
  // walk's length counts the last pause).
  CHECK(m.cycle_s() == Approx(1.0 + 4.0 + 0.5 + 2.0 + 4.0));
  CHECK_FALSE(m.pose(0.5).walking);
  CHECK(m.pose(0.5).heading_rad == Approx(0.0).margin(1e-12));  // facing the first leg from the start
  CHECK(m.pose(3.0).floor_xy.isApprox(Eigen::Vector2d(1.0, 0.0)));
  CHECK(m.pose(5.25).floor_xy.isApprox(Eigen::Vector2d(2.0, 0.0)));
  CHECK(m.pose(6.5).floor_xy.isApprox(Eigen::Vector2d(2.0, 0.5)));
  for (const double t : {7.5, 8.0, 100.0}) {
    CHECK(m.pose(t).floor_xy.isApprox(Eigen::Vector2d(2.0, 1.0)));
    CHECK_FALSE(m.pose(t).walking);
    CHECK(m.pose(t).heading_rad == Approx(std::numbers::pi / 2));  // facing the way they came
  }
  s.pauses_s = {1.0, 2.0};  // one short
  CHECK_THROWS_WITH(TeacherMotion(s), Catch::Contains("2 pauses for 3 waypoints"));
}
