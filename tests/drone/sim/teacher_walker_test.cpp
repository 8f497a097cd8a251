// The simulated teacher gives way to the drone as a person would: stops before a drone hovering in
// their way, or steps aside and walks past it; a drone beside or behind them is no obstacle.
#include <catch2/catch.hpp>

#include <cmath>

#include "drone/sim/teacher_walker.hpp"
#include "drone/sim/teacher_walk.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;

namespace {
// Along +x at y = 0 in the shipped lab's free middle (x 0.5 -> 3.5), at 0.5 m/s.
TeacherSpec straight_walk(double keep_clear_m, double side_step_m) {
  TeacherSpec spec = test::shipped_lab().teacher;
  spec.waypoints = {{0.5, 0.0}, {3.5, 0.0}};
  spec.pauses_s = {0.0, 0.0};
  spec.loop = false;
  spec.speed_mps = 0.5;
  spec.give_way = {keep_clear_m, side_step_m};
  return spec;
}

struct WalkPast {
  double nearest_gap_m = 10;  // the drone's centre from the body's edge
  double widest_aside_m = 0;
  bool stopped = false;
  double end_x = 0;
};

WalkPast walk_towards(const TeacherSpec& spec, const Eigen::Vector3d& drone, double seconds) {
  TeacherWalker walker(spec);
  WalkPast w;
  for (int k = 1; k <= static_cast<int>(seconds * 100); ++k) {
    walker.advance(k / 100.0, drone, test::shipped_lab());
    const double gap = (drone.head<2>() - walker.pose().floor_xy).norm() - spec.body_radius_m;
    w.nearest_gap_m = std::min(w.nearest_gap_m, gap);
    w.widest_aside_m = std::max(w.widest_aside_m, walker.aside_m());
    w.stopped = w.stopped || walker.giving_way();
  }
  TeacherWalker end = walker;
  w.end_x = end.pose().floor_xy.x();
  return w;
}
}  // namespace

TEST_CASE("sim teacher: a teacher stops before a drone hovering in their way, and walks on once it has gone", "[sim][teacher]") {
  const TeacherSpec spec = straight_walk(0.6, 0.0);
  const Eigen::Vector3d drone(2.5, 0.05, 1.5);
  const WalkPast w = walk_towards(spec, drone, 10.0);
  INFO("nearest gap " << w.nearest_gap_m << " m, end x " << w.end_x);
  CHECK(w.stopped);
  CHECK(w.nearest_gap_m > 0.6 - 0.01);   // within one step of the keep-clear distance
  CHECK(w.nearest_gap_m < 0.6 + 0.01);
  CHECK(w.widest_aside_m == 0.0);
  CHECK(w.end_x < 2.5 - 0.6);
  // The drone flies off: the walk goes on from where it stopped, not from where the path's time is.
  TeacherWalker walker(spec);
  for (int k = 1; k <= 1000; ++k) walker.advance(k / 100.0, drone, test::shipped_lab());
  const Eigen::Vector2d stopped_at = walker.pose().floor_xy;
  const Eigen::Matrix3d head_then = walker.pose().T_world_head.linear();
  walker.advance(10.5, Eigen::Vector3d(2.5, 2.0, 1.5), test::shipped_lab());
  CHECK_FALSE(walker.giving_way());
  CHECK(walker.pose().walking);
  CHECK((walker.pose().floor_xy - stopped_at).norm() < 0.5 * 0.5 + 1e-9);
  CHECK((walker.pose().T_world_head.linear() - head_then).norm() > 1e-3);  // the head kept turning
}

TEST_CASE("sim teacher: a teacher who side-steps walks past a drone hovering in their way", "[sim][teacher]") {
  const TeacherSpec spec = straight_walk(0.6, 0.6);
  const Eigen::Vector3d drone(2.0, 0.05, 1.5);  // a little left of the walking line: they step right
  TeacherWalker walker(spec);
  double nearest = 10, lowest_y = 0;
  for (int k = 1; k <= 1500; ++k) {
    walker.advance(k / 100.0, drone, test::shipped_lab());
    nearest = std::min(nearest, (drone.head<2>() - walker.pose().floor_xy).norm());
    lowest_y = std::min(lowest_y, walker.pose().floor_xy.y());
  }
  INFO("nearest " << nearest << " m, lowest y " << lowest_y);
  CHECK(lowest_y < -0.3);
  CHECK(nearest > spec.body_radius_m + 0.3);  // never into the hull
  CHECK(walker.pose().floor_xy.x() > 3.4);    // past it, to the walk's end
  CHECK(walker.aside_m() < 0.05);             // and back on the path there
}

TEST_CASE("sim teacher: a drone beside or behind the teacher is no obstacle", "[sim][teacher]") {
  const TeacherSpec spec = straight_walk(0.8, 0.0);
  CHECK_FALSE(walk_towards(spec, Eigen::Vector3d(2.0, 0.7, 1.5), 8.0).stopped);  // beside the corridor
  CHECK_FALSE(walk_towards(spec, Eigen::Vector3d(0.2, 0.0, 1.5), 8.0).stopped);  // behind the start
  CHECK(walk_towards(spec, Eigen::Vector3d(0.2, 0.0, 1.5), 8.0).end_x > 3.4);
}
