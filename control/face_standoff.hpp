#pragma once
// Where face-follow holds the drone: the face's standoff (standoff_target() at face_distance_m, on the
// face's line of sight), made safe and reachable. A standoff outside the geofence (a teacher facing a
// wall) is turned about the face - about the vertical through it - by the smallest angle that brings
// it inside, so the distance is kept and the face is watched from the side. A standoff far round the
// teacher from the drone (the teacher turned) is turned back so its bearing from the face leads the
// drone's by at most max_orbit_step_rad: the drone goes round the teacher, never through them, on the
// side that stays inside the fence.
#include <Eigen/Core>

#include "control/geofence.hpp"
#include "control/pid_controller.hpp"

namespace labo::control {

PoseTarget follow_standoff(PoseTarget standoff, const Eigen::Vector3d& face, const Eigen::Vector3d& drone,
                           const Geofence& fence, double max_orbit_step_rad);

// `fence` widened over the floor (x, y) to take in `seen_face`, a place where a face was seen, up to
// `limit`. The face is placed from the drone's pose estimate, so it shares that estimate's error with
// every set point placed from it: a point no nearer a wall than the face is inside the room however
// far the estimate has drifted, as the teacher is. Flown on a minute of dead reckoning the fence
// inset by the estimate's drift bound (1.5 m there) kept the drone that far from a teacher walking
// along a wall, where it saw the face from 50 degrees off its line of sight and lost it.
Geofence widened_to_face(const Geofence& fence, const Eigen::Vector3d& seen_face, const Geofence& limit);

// The same pose turned by `angle` about the vertical through `centre` (position and yaw).
PoseTarget turned_about(const PoseTarget& target, const Eigen::Vector3d& centre, double angle);

}  // namespace labo::control
