#include "localization/estimation/surface_map.hpp"

#include <algorithm>
#include <cmath>

#include "drone/lab/lab_description.hpp"

namespace labo::estimation {

using lab::Box3;
using lab::LabDescription;


double SurfaceMap::height_at(const Eigen::Vector2d& xy) const {
  double h = floor_z_;
  bool on_rect = false;
  for (const SurfaceRect& r : rects_) {
    if ((xy.array() >= r.min_xy.array()).all() && (xy.array() <= r.max_xy.array()).all()) {
      h = on_rect ? std::max(h, r.top_z) : std::max(floor_z_, r.top_z);
      on_rect = true;
    }
  }
  return h;
}

std::optional<double> SurfaceMap::unambiguous_height(const Eigen::Vector2d& xy, double margin) const {
  const double h = height_at(xy);
  // An edge of a rectangle within `margin` whose two sides differ in height makes the position
  // ambiguous: probe the square of half-size `margin` at its corners and edge midpoints.
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      if (std::abs(height_at(xy + margin * Eigen::Vector2d(i, j)) - h) > 1e-3) return std::nullopt;
    }
  }
  // A rectangle smaller than the probe grid could hide between probes: check overlap directly.
  for (const SurfaceRect& r : rects_) {
    const bool overlaps = (xy.array() + margin >= r.min_xy.array()).all() && (xy.array() - margin <= r.max_xy.array()).all();
    const bool contains = (xy.array() - margin >= r.min_xy.array()).all() && (xy.array() + margin <= r.max_xy.array()).all();
    if (overlaps && !contains && std::abs(std::max(r.top_z, floor_z_) - h) > 1e-3) return std::nullopt;
  }
  return h;
}

int SurfaceMap::heights_near(const Eigen::Vector2d& xy, double margin, double* out, int capacity) const {
  int n = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      const double h = height_at(xy + 0.5 * margin * Eigen::Vector2d(i, j));
      bool known = false;
      for (int k = 0; k < n; ++k) known = known || std::abs(out[k] - h) < 1e-3;
      if (!known && n < capacity) out[n++] = h;
    }
  }
  return n;
}

SurfaceMap surface_map_of(const LabDescription& lab) {
  SurfaceMap map(lab.room.min.z());
  const auto add_top = [&](const Box3& box) { map.add({box.min.head<2>(), box.max.head<2>(), box.max.z()}); };
  for (const auto& bench : lab.benches) add_top(bench.box);
  for (const auto& instrument : lab.instruments) add_top(instrument.bounds());
  add_top(lab.platform.box());
  return map;
}

}  // namespace labo::estimation
