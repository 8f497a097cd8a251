#pragma once
// Heights of the surfaces the ultrasound can see below the drone (floor, bench tops, the landing
// platform), as horizontal rectangles in the world. The altitude tracker uses it to tell a floor step
// from a vertical motion, and to re-anchor the ultrasound on an absolute surface height.
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace labo::lab {
struct LabDescription;
}  // namespace labo::lab

namespace labo::estimation {

struct SurfaceRect {
  Eigen::Vector2d min_xy = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_xy = Eigen::Vector2d::Zero();
  double top_z = 0.0;
};

class SurfaceMap {
 public:
  SurfaceMap() = default;
  explicit SurfaceMap(double floor_z) : floor_z_(floor_z) {}
  void add(const SurfaceRect& rect) { rects_.push_back(rect); }
  // True when only the floor is known (no raised surface): a map that cannot tell steps apart.
  bool empty() const { return rects_.empty(); }
  double floor_z() const { return floor_z_; }

  // The highest surface under (x, y); the floor when none.
  double height_at(const Eigen::Vector2d& xy) const;
  // The surface height when every point within `margin` of (x, y) has the same one (the position is
  // not near an edge); nullopt near an edge.
  std::optional<double> unambiguous_height(const Eigen::Vector2d& xy, double margin) const;
  // The surface heights found within `margin` of (x, y) (probed on a 5x5 grid), at most `capacity`
  // distinct ones written to `out`; returns how many.
  int heights_near(const Eigen::Vector2d& xy, double margin, double* out, int capacity) const;
  // Whether a surface edge with a height change lies within `margin` of (x, y).
  bool near_edge(const Eigen::Vector2d& xy, double margin) const { return !unambiguous_height(xy, margin); }

 private:
  double floor_z_ = 0.0;
  std::vector<SurfaceRect> rects_;
};

// The tops the ultrasound can see in a lab description: benches, instrument housings, the platform,
// over the room's floor.
SurfaceMap surface_map_of(const lab::LabDescription& lab);

}  // namespace labo::estimation
