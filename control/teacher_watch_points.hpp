#pragma once
// Where find-teacher waits for the teacher when the lab knows the teacher's route. The face detector
// only finds a frontal face within about 2.5 m (docs/control.md), so sweeping the room from its centre
// seldom finds a walking teacher. Instead the drone waits beyond the end of each leg of the route, on
// the leg's line, at eye height, facing back along it: the teacher then walks towards the camera,
// face frontal, and comes into the detector's range before stopping short of the drone.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "control/geofence.hpp"
#include "localization/fusion/lab_geometry.hpp"

namespace labo::control {

struct WatchPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // body, world frame
  double yaw = 0;                                      // facing the oncoming teacher
};

// One watch point per leg of at least min_leg_m: `beyond_m` past the leg's end, clamped into the
// fence; a point that ends up closer than `clearance_m` to any leg of the route (the teacher's body
// and the hull) is dropped. Empty when the route has no such leg.
std::vector<WatchPoint> teacher_watch_points(const fusion::TeacherRoute& route, const Geofence& fence, double beyond_m,
                                             double clearance_m, double min_leg_m = 1.0);

// One leg of the teacher's route: from waypoint `index` to the next (looped).
struct RouteLeg {
  std::size_t index = 0;
  std::size_t corner = 0;  // the waypoint the teacher stood nearest to when it was looked up
  Eigen::Vector2d from = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();  // unit direction of walking
  double length_m = 0;
};

// The leg a teacher standing at a corner of the route (within corner_radius_m of waypoint k, the
// nearest) walks next: the first leg of at least min_leg_m that starts at or after k. Empty when the
// teacher is not at a corner or the route has no such leg. On the route itself, never clamped into a
// fence: where the teacher walks, not where the drone may fly.
std::optional<RouteLeg> next_long_leg(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, double corner_radius_m,
                                      double min_leg_m = 1.0);

// The same from waypoint `corner` itself (the teacher standing there, or walking into it).
std::optional<RouteLeg> next_long_leg_from(const fusion::TeacherRoute& route, std::size_t corner, double min_leg_m = 1.0);

// The waypoint a teacher at `teacher_xy`, moving at `velocity`, walks into: the end of the leg whose
// line they are within `lateral_m` of, between its ends, and along which they move faster than
// `min_speed_mps`. Empty when they are on no leg or not walking along one (standing, turning).
std::optional<std::size_t> waypoint_walked_into(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy,
                                                const Eigen::Vector2d& velocity, double lateral_m, double min_speed_mps);

// How long a teacher at `teacher_xy` walking into `leg.corner` takes to set off along `leg` by the
// route: the rest of the way to the corner, a pause at each waypoint, the short legs in between.
double seconds_to_set_off(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, const RouteLeg& leg);

// Where a teacher who reached `leg.corner` `since_arrival_s` ago is by the route, until they set off
// along `leg`: pausing at each waypoint, walking the short legs in between; `leg.from` from then on.
Eigen::Vector2d route_place_before(const fusion::TeacherRoute& route, const RouteLeg& leg, double since_arrival_s);

// Where to meet a teacher who stands at a corner of the route (within corner_radius_m of waypoint k, the nearest,
// turning): `ahead_m` along the first leg of at least min_leg_m that starts at or after k, facing back
// along it - the teacher walks that leg next, towards the camera. Clamped into the fence. Empty when
// the teacher is not at a corner or the route has no such leg. The point lies on the route: only for a
// teacher whose place on it is known.
std::optional<WatchPoint> next_leg_meeting_point(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy,
                                                 const Geofence& fence, double ahead_m, double corner_radius_m,
                                                 double min_leg_m = 1.0);

// How far short of waypoint k a teacher at `teacher_xy` is along the leg that ends there (from
// waypoint k-1, looped), when within `lateral_m` of that leg's line and between its ends; negative
// when not on it. By the route a teacher stands only at waypoints: one seen on a leg, short of its end,
// walks into it.
double metres_short_of_waypoint(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, std::size_t k,
                                double lateral_m);

// Distance from p to the nearest leg of the route, loop included (floor plane); infinite without legs.
double distance_to_route(const Eigen::Vector2d& p, const fusion::TeacherRoute& route);

}  // namespace labo::control
