#include "control/geofence.hpp"

#include <cstdio>
#include <stdexcept>

namespace labo::control {

Geofence::Geofence(const Eigen::Vector3d& room_min, const Eigen::Vector3d& room_max, double margin_m)
    : min_(room_min.array() + margin_m), max_(room_max.array() - margin_m) {
  // The floor keeps no margin below the base: landing happens there.
  min_.z() = room_min.z();
  if ((min_.array() > max_.array()).any())
    throw std::invalid_argument("geofence: the room is smaller than twice the safety margin");
}

bool Geofence::contains(const Eigen::Vector3d& p) const {
  return p.allFinite() && (p.array() >= min_.array()).all() && (p.array() <= max_.array()).all();
}

Eigen::Vector3d Geofence::clamp(const Eigen::Vector3d& p) const { return p.cwiseMax(min_).cwiseMin(max_); }

double Geofence::horizontal_distance_outside_m(const Eigen::Vector3d& p) const {
  const Eigen::Vector2d xy = p.head<2>();
  return (xy - xy.cwiseMax(min_.head<2>()).cwiseMin(max_.head<2>())).norm();
}

std::string Geofence::violation(const Eigen::Vector3d& p) const {
  static constexpr const char* kAxis[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (p[i] >= min_[i] && p[i] <= max_[i]) continue;
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s = %.2f m is outside the geofence [%.2f, %.2f] m", kAxis[i], p[i], min_[i],
                  max_[i]);
    return buf;
  }
  return {};
}

}  // namespace labo::control
