#pragma once
// The room's bounds shrunk by a safety margin. Requests outside are refused; every target the
// autopilot flies to is clamped inside, so no request, mission or estimate error can send the drone
// through a wall.
#include <Eigen/Core>
#include <string>

namespace labo::control {

class Geofence {
 public:
  Geofence(const Eigen::Vector3d& room_min, const Eigen::Vector3d& room_max, double margin_m);
  bool contains(const Eigen::Vector3d& p) const;
  Eigen::Vector3d clamp(const Eigen::Vector3d& p) const;
  // Empty when inside; otherwise which bound is violated, e.g. "x = 4.20 m is outside [-2.70, 2.70]".
  std::string violation(const Eigen::Vector3d& p) const;
  // How far p lies outside the fence over the floor (x, y; 0 inside, whatever its height).
  double horizontal_distance_outside_m(const Eigen::Vector3d& p) const;
  const Eigen::Vector3d& min() const { return min_; }
  const Eigen::Vector3d& max() const { return max_; }

 private:
  Eigen::Vector3d min_;
  Eigen::Vector3d max_;
};

}  // namespace labo::control
