#pragma once
// Bilinear grey level of an 8-bit image at a sub-pixel position, for the per-sample loops of the
// trackers and the pose refinement (no bounds check: the caller keeps (x, y) in [0, size - 1)).
#include <opencv2/core.hpp>

namespace labo::planar {

inline double bilinear_grey(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const uchar* r0 = image.ptr<uchar>(y0) + x0;
  const uchar* r1 = r0 + image.step;
  const double top = r0[0] + fx * (r0[1] - r0[0]);
  const double bottom = r1[0] + fx * (r1[1] - r1[0]);
  return top + fy * (bottom - top);
}

}  // namespace labo::planar
