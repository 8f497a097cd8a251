#include "control/face_search_viewpoints.hpp"

#include <algorithm>
#include <cmath>

namespace labo::control {

std::vector<Eigen::Vector3d> face_search_viewpoints(const Geofence& fence, const estimation::SurfaceMap& surfaces,
                                                    double height_m, double spacing_m, double clearance_m) {
  const Eigen::Vector2d lo = fence.min().head<2>(), hi = fence.max().head<2>();
  const Eigen::Vector2d size = (hi - lo).cwiseMax(0.0);
  const int nx = std::max(1, static_cast<int>(std::ceil(size.x() / spacing_m)));
  const int ny = std::max(1, static_cast<int>(std::ceil(size.y() / spacing_m)));
  const double z = std::clamp(height_m, fence.min().z(), fence.max().z());
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const Eigen::Vector2d xy = lo + Eigen::Vector2d((i + 0.5) * size.x() / nx, (j + 0.5) * size.y() / ny);
      const std::optional<double> under = surfaces.unambiguous_height(xy, clearance_m);
      if (under && std::abs(*under - surfaces.floor_z()) < 1e-3) out.emplace_back(xy.x(), xy.y(), z);
    }
  }
  return out;
}

std::vector<Eigen::Vector3d> tour_from(const Eigen::Vector3d& start, std::vector<Eigen::Vector3d> viewpoints) {
  Eigen::Vector3d at = start;
  for (auto next = viewpoints.begin(); next != viewpoints.end(); ++next) {
    const auto nearest = std::min_element(next, viewpoints.end(), [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return (a - at).head<2>().squaredNorm() < (b - at).head<2>().squaredNorm();
    });
    std::iter_swap(next, nearest);
    at = *next;
  }
  return viewpoints;
}

}  // namespace labo::control
