#pragma once
// The simulated teacher's walk for one run of a randomized world: from a random point of the free
// floor to another, and on, pausing at each (turning on the spot to the next leg's direction, then
// standing a while), at one walking speed drawn for the run, the head's sway and the way they give
// way to the drone drawn too. The free floor
// is the room less a band along the walls and less the benches, the instruments and the platform,
// each grown by the body's radius and a clearance; a leg is a straight line over it. Drawn from its
// own generator seeded with the run's seed: the same seed gives the same walk.
#include <cstdint>

#include "drone/lab/lab_description.hpp"

namespace labo::sim {

struct TeacherWalkRanges {
  double min_speed_mps = 0.3, max_speed_mps = 0.7;  // one speed for the whole run
  double min_leg_m = 1.0, max_leg_m = 4.0;
  double min_stand_s = 0.0, max_stand_s = 3.0;      // standing at a waypoint, beyond the turn
  double turn_radps = 1.5;                          // turning on the spot towards the next leg
  double wall_clearance_m = 0.3;                    // the body's edge from a wall, at least
  double object_clearance_m = 0.2;                  // ... from a bench, an instrument, the platform
  double min_head_yaw_deg = 20, max_head_yaw_deg = 40;
  double min_head_yaw_period_s = 5, max_head_yaw_period_s = 10;
  double horizon_s = 600;                           // the walk lasts at least this long
  // Giving way to the drone (GiveWaySpec): how near it may come ahead, and whether the teacher
  // also steps aside (this share of the walks) and how far.
  double min_keep_clear_m = 0.4, max_keep_clear_m = 0.8;
  double side_step_share = 0.5;
  double min_side_step_m = 0.3, max_side_step_m = 0.6;
};

// The teacher of `lab` (face, eye height, body) walking a drawn path; throws std::runtime_error when
// the lab has no free floor to walk on.
lab::TeacherSpec random_teacher_walk(const lab::LabDescription& lab, std::uint64_t seed, const TeacherWalkRanges& ranges = {});

// Whether a teacher of `body_radius_m` standing at `xy` is clear of the walls by `wall_clearance_m`
// and of every object over the floor by `object_clearance_m`.
bool on_free_floor(const lab::LabDescription& lab, const Eigen::Vector2d& xy, double body_radius_m, double wall_clearance_m,
                   double object_clearance_m);

}  // namespace labo::sim
