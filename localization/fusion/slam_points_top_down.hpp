#pragma once
// The SLAM map seen from above, for the lab page's map: the map's points placed in the world with
// the estimator's map-to-world similarity (p_world = R * scale * p_map + t), kept inside the room,
// decimated to one point per grid cell and bounded. Refreshed at a low rate (the SLAM front-end
// samples its map once a second), published as an immutable snapshot shared with its readers (the
// status, the server's telemetry). The snapshots come from a small pool whose buffers are reused, so
// a refresh allocates nothing once they have grown; a refresh while every snapshot is still being
// read is skipped (the next one comes a second later).
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace labo::fusion {

struct SlamPointsXy {
  std::uint64_t revision = 0;          // a new one at each refresh
  int map_id = 0;                      // the SLAM map they were sampled from
  double cell_m = 0;                   // the decimation grid
  std::vector<Eigen::Vector2f> xy_world;  // one per occupied cell, world m
};

struct TopDownSettings {
  double cell_m = 0.10;
  std::size_t max_points = 1500;
  // Points outside the room by more than this are dropped (a badly triangulated point far away).
  double room_margin_m = 0.3;
};

// One point per occupied cell (the first in `points`' order), at most max_points of them (every
// k-th occupied cell, in the cells' order, when more are occupied); `cells` is scratch, reused.
void decimate_top_down(const std::vector<Eigen::Vector3d>& points_world, const Eigen::AlignedBox3d& room,
                       const TopDownSettings& settings, std::vector<std::pair<std::uint64_t, std::uint32_t>>& cells,
                       std::vector<Eigen::Vector2f>& out);

class SlamPointsTopDown {
 public:
  SlamPointsTopDown(const Eigen::AlignedBox3d& room, TopDownSettings settings = {});

  // Places and decimates a sample of map `map_id`; false when every snapshot is still being read.
  bool update(const std::vector<Eigen::Vector3d>& points_map, const Eigen::Matrix3d& R_world_map, double scale,
              const Eigen::Vector3d& t_world_map, int map_id);
  // The newest snapshot; null before the first update.
  std::shared_ptr<const SlamPointsXy> latest() const { return latest_; }

 private:
  Eigen::AlignedBox3d room_;
  TopDownSettings settings_;
  std::array<std::shared_ptr<SlamPointsXy>, 3> pool_;
  std::shared_ptr<const SlamPointsXy> latest_;
  std::vector<Eigen::Vector3d> world_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells_;
  std::uint64_t revision_ = 0;
};

}  // namespace labo::fusion
