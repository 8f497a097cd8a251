#pragma once
// The simulated teacher's walks the find-teacher tests fly against. The flight software is never
// told them: the tests move the face the model perception sees, nothing else.
#include "drone/lab/lab_description.hpp"
#include "drone/sim/teacher_motion.hpp"

namespace labo::test {

// The path of config/lab.json: along x at y = -2.4, back at y = -1.9, 3 s turning at each corner.
inline lab::TeacherSpec lab_path() {
  lab::TeacherSpec spec;
  spec.waypoints = {{1.2, -2.4}, {4.2, -2.4}, {4.2, -1.9}, {1.2, -1.9}};
  spec.speed_mps = 0.4;
  spec.pause_s = 3.0;
  spec.eye_height_m = 1.65;
  spec.head = lab::HeadMotionSpec{35, 7, 10, 5, 8, 9};
  return spec;
}

// Two long legs along x, 0.5 m apart, joined by short ones: a turn back at each end.
inline lab::TeacherSpec turn_back_path() {
  lab::TeacherSpec spec = lab_path();
  spec.waypoints = {{1.0, -2.0}, {3.5, -2.0}, {3.5, -1.5}, {1.0, -1.5}};
  spec.eye_height_m = 1.6;
  return spec;
}

}  // namespace labo::test
