#include "localization/fusion/slam_points_top_down.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace labo::fusion {

void decimate_top_down(const std::vector<Eigen::Vector3d>& points_world, const Eigen::AlignedBox3d& room,
                       const TopDownSettings& settings, std::vector<std::pair<std::uint64_t, std::uint32_t>>& cells,
                       std::vector<Eigen::Vector2f>& out) {
  cells.clear();
  out.clear();
  if (settings.max_points == 0 || !(settings.cell_m > 0)) return;
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(settings.room_margin_m);
  const Eigen::AlignedBox3d kept(room.min() - margin, room.max() + margin);
  for (std::size_t i = 0; i < points_world.size(); ++i) {
    const Eigen::Vector3d& p = points_world[i];
    if (!p.allFinite() || !kept.contains(p)) continue;
    // Cell indices from the kept box's corner: non-negative, and below 2^32 for any room.
    const auto ix = static_cast<std::uint64_t>((p.x() - kept.min().x()) / settings.cell_m);
    const auto iy = static_cast<std::uint64_t>((p.y() - kept.min().y()) / settings.cell_m);
    cells.emplace_back((ix << 32) | iy, static_cast<std::uint32_t>(i));
  }
  std::sort(cells.begin(), cells.end());
  const auto distinct_end = std::unique(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first == b.first; });
  const auto occupied = static_cast<std::size_t>(distinct_end - cells.begin());
  const std::size_t stride = (occupied + settings.max_points - 1) / std::max<std::size_t>(settings.max_points, 1);
  for (std::size_t c = 0; c < occupied && out.size() < settings.max_points; c += std::max<std::size_t>(stride, 1)) {
    const Eigen::Vector3d& p = points_world[cells[c].second];
    out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
}

SlamPointsTopDown::SlamPointsTopDown(const Eigen::AlignedBox3d& room, TopDownSettings settings)
    : room_(room), settings_(settings) {
  for (auto& snapshot : pool_) {
    snapshot = std::make_shared<SlamPointsXy>();
    snapshot->xy_world.reserve(settings_.max_points);
  }
}

bool SlamPointsTopDown::update(const std::vector<Eigen::Vector3d>& points_map, const Eigen::Matrix3d& R_world_map,
                               double scale, const Eigen::Vector3d& t_world_map, int map_id) {
  // A snapshot only the pool holds is read by nobody, and nobody can take it (readers copy the
  // latest one, never this one); the fence orders the readers' last accesses before our writes.
  const auto free = std::find_if(pool_.begin(), pool_.end(),
                                 [&](const std::shared_ptr<SlamPointsXy>& s) { return s.use_count() == 1 && s != latest_; });
  if (free == pool_.end()) return false;
  std::atomic_thread_fence(std::memory_order_acquire);
  world_.clear();
  for (const Eigen::Vector3d& p : points_map) world_.push_back(R_world_map * (scale * p) + t_world_map);
  SlamPointsXy& out = **free;
  decimate_top_down(world_, room_, settings_, cells_, out.xy_world);
  out.revision = ++revision_;
  out.map_id = map_id;
  out.cell_m = settings_.cell_m;
  latest_ = *free;
  return true;
}

}  // namespace labo::fusion
