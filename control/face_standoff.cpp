#include "control/face_standoff.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kFenceSearchStepRad = std::numbers::pi / 36;  // 5 degrees

double bearing(const Eigen::Vector3d& from, const Eigen::Vector3d& to) { return std::atan2(to.y() - from.y(), to.x() - from.x()); }
}  // namespace

PoseTarget turned_about(const PoseTarget& target, const Eigen::Vector3d& centre, double angle) {
  PoseTarget out = target;
  out.position = centre + Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * (target.position - centre);
  out.yaw = wrap_angle(target.yaw + angle);
  return out;
}

Geofence widened_to_face(const Geofence& fence, const Eigen::Vector3d& seen_face, const Geofence& limit) {
  Eigen::Vector3d lo = fence.min(), hi = fence.max();
  for (int i = 0; i < 2; ++i) {
    const double face_i = std::clamp(seen_face[i], limit.min()[i], limit.max()[i]);
    lo[i] = std::min(lo[i], face_i);
    hi[i] = std::max(hi[i], face_i);
  }
  return Geofence(lo, hi, 0.0);
}

PoseTarget follow_standoff(PoseTarget standoff, const Eigen::Vector3d& face, const Eigen::Vector3d& drone,
                           const Geofence& fence, double max_orbit_step_rad) {
  if (!fence.contains(standoff.position)) {
    for (double a = kFenceSearchStepRad; a <= std::numbers::pi; a += kFenceSearchStepRad) {
      if (const PoseTarget left = turned_about(standoff, face, a); fence.contains(left.position)) {
        standoff = left;
        break;
      }
      if (const PoseTarget right = turned_about(standoff, face, -a); fence.contains(right.position)) {
        standoff = right;
        break;
      }
    }
  }
  const double lead = wrap_angle(bearing(face, standoff.position) - bearing(face, drone));
  if (std::abs(lead) <= max_orbit_step_rad) return standoff;
  // Go round the side that stays inside the fence (the short way first).
  const PoseTarget short_way = turned_about(standoff, face, std::copysign(max_orbit_step_rad, lead) - lead);
  if (fence.contains(short_way.position)) return short_way;
  const double long_lead = lead - std::copysign(2 * std::numbers::pi, lead);
  return turned_about(standoff, face, std::copysign(max_orbit_step_rad, long_lead) - long_lead);
}

}  // namespace labo::control
