#include "core/camera_model.hpp"

#include <cmath>
#include <stdexcept>

namespace labo {

void validate(const CameraIntrinsics& k, const std::string& name) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument("camera '" + name + "': " + what); };
  for (double v : {k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3, k.calibration_error_px}) {
    if (!std::isfinite(v)) fail("intrinsics must be finite numbers");
  }
  if (k.calibration_error_px < 0) fail("calibration_error_px must be zero or positive");
  if (k.width <= 0 || k.height <= 0) {
    fail("image size " + std::to_string(k.width) + "x" + std::to_string(k.height) + " must be positive");
  }
  if (k.fx <= 0 || k.fy <= 0) fail("focal lengths fx, fy must be positive");
  if (k.cx < 0 || k.cx > k.width || k.cy < 0 || k.cy > k.height) {
    fail("principal point (cx, cy) must lie inside the image");
  }
}

PinholeCamera::PinholeCamera(const CameraIntrinsics& intrinsics) : k_(intrinsics) { validate(k_, "camera"); }

PinholeCamera PinholeCamera::ardrone2_front() {
  return PinholeCamera({640, 360, 569.9, 568.0, 331.4, 135.9, -0.527, 0.274, 0.021, -0.006, 0.0});
}

PinholeCamera PinholeCamera::ardrone2_bottom() {
  return PinholeCamera({640, 360, 700.5, 701.7, 319.5, 218.7, 0, 0, 0, 0, 0});
}

bool PinholeCamera::has_distortion() const {
  return k_.k1 != 0 || k_.k2 != 0 || k_.p1 != 0 || k_.p2 != 0 || k_.k3 != 0;
}

cv::Matx33d PinholeCamera::K() const { return {k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1}; }

cv::Mat PinholeCamera::distortion_coefficients() const {
  return (cv::Mat_<double>(1, 5) << k_.k1, k_.k2, k_.p1, k_.p2, k_.k3);
}

Eigen::Vector2d PinholeCamera::distort(const Eigen::Vector2d& u) const {
  const double x = u.x(), y = u.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + k_.k1 * r2 + k_.k2 * r2 * r2 + k_.k3 * r2 * r2 * r2;
  return {x * radial + 2 * k_.p1 * x * y + k_.p2 * (r2 + 2 * x * x),
          y * radial + k_.p1 * (r2 + 2 * y * y) + 2 * k_.p2 * x * y};
}

Eigen::Vector2d PinholeCamera::undistort(const Eigen::Vector2d& d) const {
  if (!has_distortion()) return d;
  // Newton-free fixed point: u <- u + (d - distort(u)). Stops when the residual is below 1e-12
  // (well under a thousandth of a pixel).
  Eigen::Vector2d u = d;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector2d r = d - distort(u);
    u += r;
    if (r.squaredNorm() < 1e-24) break;
  }
  return u;
}

std::optional<Eigen::Vector2d> PinholeCamera::project(const Eigen::Vector3d& p) const {
  if (p.z() <= 1e-3) return std::nullopt;
  const Eigen::Vector2d d = distort({p.x() / p.z(), p.y() / p.z()});
  return Eigen::Vector2d(k_.fx * d.x() + k_.cx, k_.fy * d.y() + k_.cy);
}

Eigen::Vector3d PinholeCamera::unproject(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d d((px.x() - k_.cx) / k_.fx, (px.y() - k_.cy) / k_.fy);
  const Eigen::Vector2d u = undistort(d);
  return Eigen::Vector3d(u.x(), u.y(), 1.0).normalized();
}

bool PinholeCamera::in_image(const Eigen::Vector2d& px, double margin) const {
  return px.x() >= margin && px.y() >= margin && px.x() <= k_.width - 1 - margin &&
         px.y() <= k_.height - 1 - margin;
}

PinholeCamera PinholeCamera::scaled(double f) const {
  CameraIntrinsics k = k_;
  k.width = static_cast<int>(std::lround(k_.width * f));
  k.height = static_cast<int>(std::lround(k_.height * f));
  k.fx *= f;
  k.fy *= f;
  // Pixel centres: (c + 0.5) * f - 0.5 keeps the grid aligned when resizing with cv::resize.
  k.cx = (k_.cx + 0.5) * f - 0.5;
  k.cy = (k_.cy + 0.5) * f - 0.5;
  return PinholeCamera(k);
}

PinholeCamera PinholeCamera::without_distortion() const {
  CameraIntrinsics k = k_;
  k.k1 = k.k2 = k.p1 = k.p2 = k.k3 = 0;
  return PinholeCamera(k);
}

}  // namespace labo
