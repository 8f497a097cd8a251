// The simulated teacher's drawn walk: on the free floor, within its ranges, the same for the same seed.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "drone/sim/teacher_motion.hpp"
#include "drone/sim/teacher_walk.hpp"
#include "tests/drone/sim/sim_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;

TEST_CASE("sim teacher walk: legs over the free floor, speed and pauses in their ranges, as long as the horizon", "[sim][teacher]") {
  const LabDescription& lab = test::shipped_lab();
  const TeacherWalkRanges r;
  const double radius = lab.teacher.body_radius_m;
  double slowest = 10, fastest = 0, shortest_leg = 10, longest_leg = 0;
  int side_steppers = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const TeacherSpec w = random_teacher_walk(lab, seed, r);
    INFO("seed " << seed);
    CHECK_FALSE(w.loop);
    REQUIRE(w.pauses_s.size() == w.waypoints.size());
    REQUIRE(w.waypoints.size() > 10);
    CHECK(w.speed_mps >= r.min_speed_mps);
    CHECK(w.speed_mps <= r.max_speed_mps);
    CHECK(w.head.yaw_amplitude_deg >= r.min_head_yaw_deg);
    CHECK(w.head.yaw_amplitude_deg <= r.max_head_yaw_deg);
    CHECK(w.face_image == lab.teacher.face_image);  // the same teacher, walking elsewhere
    CHECK(w.eye_height_m == lab.teacher.eye_height_m);
    CHECK(w.give_way.keep_clear_m >= r.min_keep_clear_m);
    CHECK(w.give_way.keep_clear_m <= r.max_keep_clear_m);
    if (w.give_way.side_step_m > 0) {
      ++side_steppers;
      CHECK(w.give_way.side_step_m >= r.min_side_step_m);
      CHECK(w.give_way.side_step_m <= r.max_side_step_m);
    }
    slowest = std::min(slowest, w.speed_mps);
    fastest = std::max(fastest, w.speed_mps);
    for (std::size_t i = 0; i < w.waypoints.size(); ++i) {
      CHECK(w.pauses_s[i] >= r.min_stand_s);
      CHECK(w.pauses_s[i] <= r.max_stand_s + std::numbers::pi / r.turn_radps + 1e-9);
      if (i + 1 == w.waypoints.size()) break;
      const Eigen::Vector2d a = w.waypoints[i], b = w.waypoints[i + 1];
      shortest_leg = std::min(shortest_leg, (b - a).norm());
      longest_leg = std::max(longest_leg, (b - a).norm());
      // Every point of the leg, within the probes' resolution (legs are checked every 0.1 m, objects
      // probed on a 5 x 5 grid).
      for (int k = 0; k <= 20; ++k)
        CHECK(on_free_floor(lab, a + (b - a) * (k / 20.0), radius, r.wall_clearance_m, r.object_clearance_m - 0.1));
    }
    CHECK(TeacherMotion(w).cycle_s() >= r.horizon_s);
  }
  // The ranges are used, not just respected.
  CHECK(slowest < r.min_speed_mps + 0.05);
  CHECK(fastest > r.max_speed_mps - 0.05);
  CHECK(shortest_leg >= r.min_leg_m - 1e-9);
  CHECK(longest_leg <= r.max_leg_m + 1e-9);
  CHECK(longest_leg > r.max_leg_m - 0.3);
  CHECK(side_steppers > 5);  // some stop, some step aside
  CHECK(side_steppers < 35);
}

TEST_CASE("sim teacher walk: the same seed walks the same path, another seed another", "[sim][teacher]") {
  const LabDescription& lab = test::shipped_lab();
  const TeacherSpec a = random_teacher_walk(lab, 5), b = random_teacher_walk(lab, 5), c = random_teacher_walk(lab, 6);
  REQUIRE(a.waypoints.size() == b.waypoints.size());
  for (std::size_t i = 0; i < a.waypoints.size(); ++i) CHECK(a.waypoints[i] == b.waypoints[i]);
  CHECK(a.speed_mps == b.speed_mps);
  CHECK(a.waypoints[1] != c.waypoints[1]);
  CHECK(a.speed_mps != c.speed_mps);
}

TEST_CASE("sim teacher walk: the benches, the instruments, the platform and the walls are not free floor", "[sim][teacher]") {
  const LabDescription& lab = test::shipped_lab();
  CHECK(on_free_floor(lab, {2.0, 0.0}, 0.25, 0.3, 0.2));
  CHECK_FALSE(on_free_floor(lab, {6.0, -1.0}, 0.25, 0.3, 0.2));  // on the east bench
  CHECK_FALSE(on_free_floor(lab, {5.3, -1.0}, 0.25, 0.3, 0.2));  // its edge within the body and clearance
  CHECK_FALSE(on_free_floor(lab, {0.0, 0.0}, 0.25, 0.3, 0.2));   // the platform
  CHECK_FALSE(on_free_floor(lab, {-1.1, 0.0}, 0.25, 0.3, 0.2));  // 0.4 m from the west wall
  LabDescription boxed = lab;
  boxed.benches.push_back({"everywhere", {lab.room.min, Eigen::Vector3d(lab.room.max.x(), lab.room.max.y(), 0.9)}});
  CHECK_THROWS_AS(random_teacher_walk(boxed, 1), std::runtime_error);
}
