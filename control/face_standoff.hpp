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

// The same pose turned by `angle` about the vertical through `centre` (position and yaw).
PoseTarget turned_about(const PoseTarget& target, const Eigen::Vector3d& centre, double angle);

}  // namespace labo::control
