#include "drone/sim/collision_model.hpp"

#include <algorithm>

namespace labo::sim {

using lab::Box3;
using lab::LabDescription;


namespace {
// A top face up to this far above the underside still counts as below it (resting contact).
constexpr double kRestTolerance_m = 0.02;
}  // namespace

CollisionModel::CollisionModel(const LabDescription& lab, HullShape hull) : hull_(hull), room_(lab.room) {
  for (const auto& b : lab.benches) obstacles_.push_back({b.id, b.box});
  for (const auto& i : lab.instruments) obstacles_.push_back({i.id, i.bounds()});
  obstacles_.push_back({lab.platform.id.empty() ? "platform" : lab.platform.id, lab.platform.box()});
}

void CollisionModel::set_teacher(const std::optional<Eigen::Vector2d>& floor_xy, double radius_m, double height_m) {
  teacher_xy_ = floor_xy;
  teacher_radius_m_ = radius_m;
  teacher_height_m_ = height_m;
}

bool CollisionModel::footprint_overlaps(const Eigen::Vector3d& p, const Box3& box) const {
  // Closest point of the box's footprint to the disc's centre.
  const double cx = std::clamp(p.x(), box.min.x(), box.max.x());
  const double cy = std::clamp(p.y(), box.min.y(), box.max.y());
  const double dx = p.x() - cx, dy = p.y() - cy;
  return dx * dx + dy * dy < hull_.radius_m * hull_.radius_m;
}

std::optional<std::string> CollisionModel::obstacle_hit(const Eigen::Vector3d& p) const {
  const double r = hull_.radius_m;
  if (p.x() - r < room_.min.x()) return "wall_xmin";
  if (p.x() + r > room_.max.x()) return "wall_xmax";
  if (p.y() - r < room_.min.y()) return "wall_ymin";
  if (p.y() + r > room_.max.y()) return "wall_ymax";
  if (p.z() + hull_.height_m > room_.max.z()) return "ceiling";
  const double bottom = p.z(), top = p.z() + hull_.height_m;
  for (const auto& o : obstacles_) {
    const bool above = bottom >= o.box.max.z() - kRestTolerance_m;
    if (!above && top > o.box.min.z() && footprint_overlaps(p, o.box)) return o.id;
  }
  if (teacher_xy_ && bottom < teacher_height_m_ &&
      (p.head<2>() - *teacher_xy_).norm() < r + teacher_radius_m_) {
    return "teacher";
  }
  return std::nullopt;
}

double CollisionModel::support_height(const Eigen::Vector3d& p) const {
  double h = room_.min.z();
  for (const auto& o : obstacles_) {
    if (p.z() >= o.box.max.z() - kRestTolerance_m && footprint_overlaps(p, o.box)) h = std::max(h, o.box.max.z());
  }
  return h;
}

}  // namespace labo::sim
