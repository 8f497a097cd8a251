#pragma once
// Teacher routes and the simulated teacher walking them, shared by the find-teacher tests.
#include "localization/fusion/lab_geometry.hpp"
#include "drone/sim/teacher_motion.hpp"
#include "drone/lab/lab_description.hpp"

namespace labo::test {

// The route of config/lab.json: along x at y = -2.4, back at y = -1.9.
inline fusion::TeacherRoute lab_route() {
  fusion::TeacherRoute r;
  r.waypoints = {{1.2, -2.4}, {4.2, -2.4}, {4.2, -1.9}, {1.2, -1.9}};
  r.speed_mps = 0.4;
  r.pause_s = 3.0;
  r.eye_height_m = 1.65;
  return r;
}

// Two long legs along x, 0.5 m apart, joined by short ones: a turn back at each end.
inline fusion::TeacherRoute turn_back_route() {
  fusion::TeacherRoute r;
  r.waypoints = {{1.0, -2.0}, {3.5, -2.0}, {3.5, -1.5}, {1.0, -1.5}};
  r.speed_mps = 0.4;
  r.pause_s = 3.0;
  r.eye_height_m = 1.6;
  return r;
}

// The simulated teacher walking `route`, with the lab's head sway.
inline TeacherSpec walking(const fusion::TeacherRoute& route) {
  TeacherSpec spec;
  spec.waypoints = route.waypoints;
  spec.speed_mps = route.speed_mps;
  spec.pause_s = route.pause_s;
  spec.eye_height_m = route.eye_height_m;
  spec.head = HeadMotionSpec{35, 7, 10, 5, 8, 9};
  return spec;
}

}  // namespace labo::test
