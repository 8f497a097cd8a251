#pragma once
// What a camera's pixel records of a planar panel, by brute force, for the planar tests' references:
// the mean of sub x sub rays through the pixel's square and the lens (distortion included) onto the
// panel's plane (object frame of planar_template.hpp), each the nearest texel of the template (the
// texels piecewise constant), `background` where a ray misses the panel.
#include <cmath>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/camera_model.hpp"

namespace labo {

inline double supersampled_pixel(const PinholeCamera& camera, const cv::Mat& panel, double width_m, double height_m,
                                 const Eigen::Isometry3d& T_object_cam, int x, int y, int sub, double background) {
  double sum = 0;
  for (int j = 0; j < sub; ++j) {
    for (int i = 0; i < sub; ++i) {
      const Eigen::Vector2d point(x - 0.5 + (i + 0.5) / sub, y - 0.5 + (j + 0.5) / sub);
      const Eigen::Vector3d ray = T_object_cam.linear() * camera.unproject(point);
      const Eigen::Vector3d o = T_object_cam.translation();
      const double s = -o.z() / ray.z();
      const Eigen::Vector3d p = o + s * ray;
      const int u = static_cast<int>(std::floor((p.x() / width_m + 0.5) * panel.cols));
      const int v = static_cast<int>(std::floor((p.y() / height_m + 0.5) * panel.rows));
      sum += (s > 0 && u >= 0 && v >= 0 && u < panel.cols && v < panel.rows) ? panel.at<uchar>(v, u) : background;
    }
  }
  return sum / (sub * sub);
}

}  // namespace labo
