#include "bench/planar/planar_sequence.hpp"

namespace labo::bench {

double visible_fraction(const PinholeCamera& camera, const PanelModel& panel, const Eigen::Isometry3d& T_cam_object) {
  int inside = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) {
      const Eigen::Vector3d p((i / 8.0 - 0.5) * panel.width_m, (j / 8.0 - 0.5) * panel.height_m, 0);
      const auto px = camera.project(T_cam_object * p);
      if (px && camera.in_image(*px)) ++inside;
    }
  }
  return inside / 81.0;
}

}  // namespace labo::bench
