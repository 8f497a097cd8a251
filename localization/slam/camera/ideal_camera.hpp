#pragma once
// The SLAM works in "ideal pixels": the pixel a point would have through the same focal lengths and
// principal point without lens distortion. Keypoints are undistorted once, through a lookup table
// built at start (the AR.Drone's front lens has k1 = -0.53, far from negligible); residuals, epipolar
// geometry and PnP then use the plain pinhole model. Visibility is still decided in the real,
// distorted image.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "core/camera_model.hpp"

namespace labo::slam {

class IdealCamera {
 public:
  explicit IdealCamera(const PinholeCamera& real);

  const PinholeCamera& real() const { return real_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  cv::Matx33d K() const { return {fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1}; }

  // Ideal pixel of a (distorted) level-0 image pixel, bilinear in the lookup table.
  Eigen::Vector2d ideal_from_image(double u, double v) const;
  // Ideal pixel of a point in camera coordinates; empty behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_cam) const {
    if (p_cam.z() <= 1e-6) return std::nullopt;
    return Eigen::Vector2d(fx_ * p_cam.x() / p_cam.z() + cx_, fy_ * p_cam.y() / p_cam.z() + cy_);
  }
  // True when the point lands inside the real image (with a margin in image pixels).
  bool visible(const Eigen::Vector3d& p_cam, double margin_px) const;
  Eigen::Vector3d bearing(const Eigen::Vector2d& ideal_px) const {
    return Eigen::Vector3d((ideal_px.x() - cx_) / fx_, (ideal_px.y() - cy_) / fy_, 1.0).normalized();
  }
  // Bounding box of the image in ideal pixels (for the search grid).
  const Eigen::Vector2d& ideal_min() const { return ideal_min_; }
  const Eigen::Vector2d& ideal_max() const { return ideal_max_; }

 private:
  PinholeCamera real_;
  double fx_, fy_, cx_, cy_;
  cv::Mat lut_;  // CV_32FC2, image size: ideal pixel of each image pixel
  Eigen::Vector2d ideal_min_, ideal_max_;
};

}  // namespace labo::slam
