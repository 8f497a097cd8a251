#include "localization/slam/camera/ideal_camera.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::slam {

IdealCamera::IdealCamera(const PinholeCamera& real)
    : real_(real),
      fx_(real.intrinsics().fx),
      fy_(real.intrinsics().fy),
      cx_(real.intrinsics().cx),
      cy_(real.intrinsics().cy),
      lut_(real.height(), real.width(), CV_32FC2) {
  ideal_min_ = Eigen::Vector2d::Constant(1e9);
  ideal_max_ = Eigen::Vector2d::Constant(-1e9);
  for (int v = 0; v < real.height(); ++v) {
    auto* row = lut_.ptr<cv::Vec2f>(v);
    for (int u = 0; u < real.width(); ++u) {
      const Eigen::Vector2d d((u - cx_) / fx_, (v - cy_) / fy_);
      const Eigen::Vector2d n = real.undistort(d);
      // A lens whose distortion folds over inside the image has no inverse there: refuse it rather
      // than build a table of garbage (the SLAM would then run on wrong geometry).
      const Eigen::Vector2d back = real.distort(n);
      if (!n.allFinite() || std::hypot((back.x() - d.x()) * fx_, (back.y() - d.y()) * fy_) > 0.01) {
        throw std::invalid_argument("slam camera: the lens distortion cannot be inverted at pixel (" + std::to_string(u) + ", " +
                                    std::to_string(v) + "); check the distortion coefficients");
      }
      const Eigen::Vector2d p(fx_ * n.x() + cx_, fy_ * n.y() + cy_);
      row[u] = cv::Vec2f(static_cast<float>(p.x()), static_cast<float>(p.y()));
      ideal_min_ = ideal_min_.cwiseMin(p);
      ideal_max_ = ideal_max_.cwiseMax(p);
    }
  }
}

Eigen::Vector2d IdealCamera::ideal_from_image(double u, double v) const {
  u = std::clamp(u, 0.0, static_cast<double>(lut_.cols - 1));
  v = std::clamp(v, 0.0, static_cast<double>(lut_.rows - 1));
  const int u0 = std::min(static_cast<int>(u), lut_.cols - 2);
  const int v0 = std::min(static_cast<int>(v), lut_.rows - 2);
  const double a = u - u0, b = v - v0;
  const cv::Vec2f p00 = lut_.at<cv::Vec2f>(v0, u0), p01 = lut_.at<cv::Vec2f>(v0, u0 + 1);
  const cv::Vec2f p10 = lut_.at<cv::Vec2f>(v0 + 1, u0), p11 = lut_.at<cv::Vec2f>(v0 + 1, u0 + 1);
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) {
    out[i] = (1 - a) * (1 - b) * p00[i] + a * (1 - b) * p01[i] + (1 - a) * b * p10[i] + a * b * p11[i];
  }
  return out;
}

bool IdealCamera::visible(const Eigen::Vector3d& p_cam, double margin_px) const {
  const auto px = real_.project(p_cam);
  if (!px) return false;
  // Strong barrel distortion folds far-off-axis rays back into the image: refuse rays more than
  // ~60 degrees off axis, which the lens does not see anyway.
  const double off_axis = std::hypot(p_cam.x(), p_cam.y()) / p_cam.z();
  return off_axis < 1.8 && real_.in_image(*px, margin_px);
}

}  // namespace labo::slam
