#include "control/teacher_watch_points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace labo::control {

namespace {
double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 1e-12 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

// Where a point lies relative to the leg into waypoint k (from k-1, looped).
struct PlaceOnLeg {
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();
  double length_m = 0;
  double s_m = 0;        // along the leg from its start
  double lateral_m = 0;  // off its line
};

std::optional<PlaceOnLeg> place_on_leg_into(const fusion::TeacherRoute& route, std::size_t k, const Eigen::Vector2d& p) {
  const std::size_t n = route.waypoints.size();
  if (n < 2) return std::nullopt;
  const Eigen::Vector2d to = route.waypoints[k % n], from = route.waypoints[(k + n - 1) % n];
  const double length = (to - from).norm();
  if (length < 1e-9) return std::nullopt;
  const Eigen::Vector2d along = (to - from) / length;
  const Eigen::Vector2d rel = p - from;
  return PlaceOnLeg{along, length, rel.dot(along), std::abs(along.x() * rel.y() - along.y() * rel.x())};
}
}  // namespace

double distance_to_route(const Eigen::Vector2d& p, const fusion::TeacherRoute& route) {
  const std::size_t n = route.waypoints.size();
  double nearest = n == 1 ? (p - route.waypoints[0]).norm() : std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; n > 1 && i < n; ++i)
    nearest = std::min(nearest, distance_to_segment(p, route.waypoints[i], route.waypoints[(i + 1) % n]));
  return nearest;
}

std::vector<WatchPoint> teacher_watch_points(const fusion::TeacherRoute& route, const Geofence& fence, double beyond_m,
                                             double clearance_m, double min_leg_m) {
  std::vector<WatchPoint> out;
  const std::size_t n = route.waypoints.size();
  if (n < 2) return out;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d from = route.waypoints[i], to = route.waypoints[(i + 1) % n];
    const Eigen::Vector2d leg = to - from;
    if (leg.norm() < min_leg_m) continue;
    const Eigen::Vector2d along = leg.normalized();
    const Eigen::Vector2d p = to + beyond_m * along;
    const Eigen::Vector3d clamped = fence.clamp({p.x(), p.y(), route.eye_height_m});
    if (distance_to_route(clamped.head<2>(), route) < clearance_m) continue;
    // Face back along the leg, towards where the teacher comes from.
    out.push_back({clamped, std::atan2(-along.y(), -along.x())});
  }
  return out;
}

std::optional<RouteLeg> next_long_leg(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, double corner_radius_m,
                                      double min_leg_m) {
  const std::size_t n = route.waypoints.size();
  if (n < 2) return std::nullopt;
  std::size_t corner = n;  // the nearest waypoint within corner_radius_m (two can be, round a short leg)
  double nearest = corner_radius_m;
  for (std::size_t k = 0; k < n; ++k) {
    if (const double d = (route.waypoints[k] - teacher_xy).norm(); d < nearest) {
      nearest = d;
      corner = k;
    }
  }
  if (corner == n) return std::nullopt;
  return next_long_leg_from(route, corner, min_leg_m);
}

std::optional<RouteLeg> next_long_leg_from(const fusion::TeacherRoute& route, std::size_t corner, double min_leg_m) {
  const std::size_t n = route.waypoints.size();
  if (n < 2 || corner >= n) return std::nullopt;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t leg = (corner + i) % n;
    const Eigen::Vector2d from = route.waypoints[leg], to = route.waypoints[(leg + 1) % n];
    if ((to - from).norm() < min_leg_m) continue;
    return RouteLeg{leg, corner, from, (to - from).normalized(), (to - from).norm()};
  }
  return std::nullopt;
}

double seconds_to_set_off(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, const RouteLeg& leg) {
  const std::size_t n = route.waypoints.size();
  const double speed = std::max(route.speed_mps, 1e-3);
  const double pause = std::max(route.pause_s, 0.0);
  double s = (route.waypoints[leg.corner % n] - teacher_xy).norm() / speed + pause;
  for (std::size_t k = leg.corner % n; k != leg.index % n; k = (k + 1) % n)
    s += (route.waypoints[(k + 1) % n] - route.waypoints[k]).norm() / speed + pause;
  return s;
}

double metres_short_of_waypoint(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy, std::size_t k,
                                double lateral_m) {
  const std::optional<PlaceOnLeg> on = place_on_leg_into(route, k, teacher_xy);
  if (!on) return -1.0;
  return on->lateral_m <= lateral_m && on->s_m >= 0.0 && on->s_m <= on->length_m ? on->length_m - on->s_m : -1.0;
}

std::optional<std::size_t> waypoint_walked_into(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy,
                                                const Eigen::Vector2d& velocity, double lateral_m, double min_speed_mps) {
  std::optional<std::size_t> best;
  double best_lateral = lateral_m;
  for (std::size_t k = 0; k < route.waypoints.size(); ++k) {
    const std::optional<PlaceOnLeg> on = place_on_leg_into(route, k, teacher_xy);
    // The nearest line wins: a leg walked back alongside another (0.5 m apart in the lab) is no part of it.
    if (!on || on->s_m < 0.0 || on->s_m > on->length_m || on->lateral_m > best_lateral ||
        velocity.dot(on->along) <= min_speed_mps)
      continue;
    best = k;
    best_lateral = on->lateral_m;
  }
  return best;
}

Eigen::Vector2d route_place_before(const fusion::TeacherRoute& route, const RouteLeg& leg, double since_arrival_s) {
  const std::size_t n = route.waypoints.size();
  const double speed = std::max(route.speed_mps, 1e-3);
  double left = since_arrival_s - std::max(route.pause_s, 0.0);  // time left after the pause at k
  std::size_t k = leg.corner % n;
  for (; k != leg.index % n && left > 0; k = (k + 1) % n) {
    const Eigen::Vector2d from = route.waypoints[k], to = route.waypoints[(k + 1) % n];
    const double walk_s = (to - from).norm() / speed;
    if (left < walk_s) return from + (left / walk_s) * (to - from);
    left -= walk_s + std::max(route.pause_s, 0.0);
  }
  return route.waypoints[k];
}

std::optional<WatchPoint> next_leg_meeting_point(const fusion::TeacherRoute& route, const Eigen::Vector2d& teacher_xy,
                                                 const Geofence& fence, double ahead_m, double corner_radius_m,
                                                 double min_leg_m) {
  const std::optional<RouteLeg> leg = next_long_leg(route, teacher_xy, corner_radius_m, min_leg_m);
  if (!leg) return std::nullopt;
  const Eigen::Vector2d p = leg->from + std::min(ahead_m, leg->length_m) * leg->along;
  return WatchPoint{fence.clamp({p.x(), p.y(), route.eye_height_m}), std::atan2(-leg->along.y(), -leg->along.x())};
}

}  // namespace labo::control
