#pragma once
// TeacherMotion: the simulated teacher's walk: the lab file's scripted path (lab.json "teacher"), or
// a walk drawn for the run (teacher_walk.hpp). The teacher stands at the first waypoint, then walks
// the waypoints in order at `speed_mps`, pausing at each one (`pauses_s`, else `pause_s`) while
// turning from the incoming to the outgoing direction; a looped path goes back to the first, a drawn
// walk ends standing at its last waypoint. The head turns relative to the walking direction as three
// sinusoids (yaw, pitch, roll). A pure function of time: the same t gives the same pose, whatever was
// asked before.
//
// Head pose in the CANDIDE-3 face frame of core/candide3.hpp: origin between the eyes at eye height,
// +x the subject's left, +y up, +z out of the face. Head yaw > 0 turns to the subject's left, pitch
// > 0 looks down, roll > 0 tilts the top of the head towards the subject's right.
#include <Eigen/Geometry>
#include <vector>

#include "core/time.hpp"
#include "drone/lab/lab_description.hpp"

namespace labo::sim {

struct TeacherPose {
  Eigen::Vector2d floor_xy = Eigen::Vector2d::Zero();
  double heading_rad = 0;  // the body's facing direction in the world, counter-clockwise from +x
  Eigen::Isometry3d T_world_head = Eigen::Isometry3d::Identity();
  bool walking = false;
};

class TeacherMotion {
 public:
  // Throws std::invalid_argument when the path has no waypoint, the speed is not positive or the
  // pauses are not one per waypoint.
  explicit TeacherMotion(const lab::TeacherSpec& spec);
  TeacherPose pose(Seconds t) const { return pose(t, t); }
  // Where the walk has got after `walk_t` seconds of walking and standing, the head turned as at
  // `head_t` (a teacher who stopped for the drone walks on later than the path's time; the head
  // keeps turning meanwhile).
  TeacherPose pose(Seconds walk_t, Seconds head_t) const;
  // One round of a looped path; the whole walk of one that does not loop.
  Seconds cycle_s() const { return cycle_s_; }

 private:
  struct Leg {
    Eigen::Vector2d from, to;
    Seconds pause_start = 0, walk_start = 0, walk_end = 0;  // within one cycle
    double heading_in = 0, heading_out = 0;     // arriving at `from`, leaving it
  };
  lab::TeacherSpec spec_;
  std::vector<Leg> legs_;
  Seconds cycle_s_ = 0;
};

}  // namespace labo::sim
