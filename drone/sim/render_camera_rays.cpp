#include "drone/sim/render_camera_rays.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::sim {

namespace {

// Undistorted normalized coordinates of a pixel: Newton's method on the camera model's own forward
// distortion, so that camera.project() of a traced point lands on its pixel. `guess` is the solution
// of a neighbouring pixel (two or three steps then suffice), or empty to start from the camera's inverse.
Eigen::Vector2d invert_lens(const PinholeCamera& camera, const Eigen::Vector2d& pixel, const Eigen::Vector2d* guess) {
  const auto& k = camera.intrinsics();
  const Eigen::Vector2d d((pixel.x() - k.cx) / k.fx, (pixel.y() - k.cy) / k.fy);
  if (!camera.has_distortion()) return d;
  Eigen::Vector2d u = guess ? *guess : camera.undistort(d);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d f = camera.distort(u);
    const Eigen::Vector2d r = f - d;
    if (r.squaredNorm() < 1e-26) break;
    constexpr double h = 1e-7;
    Eigen::Matrix2d J;
    J.col(0) = (camera.distort(u + Eigen::Vector2d(h, 0)) - f) / h;
    J.col(1) = (camera.distort(u + Eigen::Vector2d(0, h)) - f) / h;
    u -= J.inverse() * r;
  }
  return u;
}

}  // namespace

CameraRays::CameraRays(const PinholeCamera& camera) : camera_(camera) {
  const int w = camera.width(), h = camera.height();
  const auto& k = camera.intrinsics();
  x_.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  y_.resize(x_.size());
  Eigen::Vector2d row_start = Eigen::Vector2d::Zero();
  for (int py = 0; py < h; ++py) {
    Eigen::Vector2d previous = Eigen::Vector2d::Zero();
    for (int px = 0; px < w; ++px) {
      const Eigen::Vector2d* guess = px > 0 ? &previous : (py > 0 ? &row_start : nullptr);
      const Eigen::Vector2d u = invert_lens(camera, {px, py}, guess);
      previous = u;
      if (px == 0) row_start = u;
      const Eigen::Vector2d back = camera.distort(u);
      const double err_px = std::hypot((back.x() - (px - k.cx) / k.fx) * k.fx, (back.y() - (py - k.cy) / k.fy) * k.fy);
      if (!(err_px < 0.01)) {
        throw std::invalid_argument("camera rays: the lens distortion cannot be inverted at pixel (" + std::to_string(px) +
                                    ", " + std::to_string(py) + "): check the distortion coefficients");
      }
      const std::size_t i = static_cast<std::size_t>(py) * static_cast<std::size_t>(w) + static_cast<std::size_t>(px);
      x_[i] = static_cast<float>(u.x());
      y_[i] = static_cast<float>(u.y());
      max_radius_ = std::max(max_radius_, static_cast<float>(u.norm()));
      min_x_ = std::min(min_x_, x_[i]);
      max_x_ = std::max(max_x_, x_[i]);
      min_y_ = std::min(min_y_, y_[i]);
      max_y_ = std::max(max_y_, y_[i]);
    }
  }
  pixel_angle_ = static_cast<float>(2.0 / (k.fx + k.fy));
  tiles_x_ = (w + kTile - 1) / kTile;
  tiles_y_ = (h + kTile - 1) / kTile;
  for (int ty = 0; ty < tiles_y_; ++ty) {
    for (int tx = 0; tx < tiles_x_; ++tx) {
      RenderTile t;
      t.x0 = tx * kTile;
      t.y0 = ty * kTile;
      t.x1 = std::min(w, t.x0 + kTile);
      t.y1 = std::min(h, t.y0 + kTile);
      t.min_x = t.min_y = 1e9f;
      t.max_x = t.max_y = -1e9f;
      for (int py = t.y0; py < t.y1; ++py) {
        for (int px = t.x0; px < t.x1; ++px) {
          const std::size_t i = static_cast<std::size_t>(py) * static_cast<std::size_t>(w) + static_cast<std::size_t>(px);
          t.min_x = std::min(t.min_x, x_[i]);
          t.max_x = std::max(t.max_x, x_[i]);
          t.min_y = std::min(t.min_y, y_[i]);
          t.max_y = std::max(t.max_y, y_[i]);
        }
      }
      t.centre = ((t.y0 + t.y1) / 2) * w + (t.x0 + t.x1) / 2;
      tiles_.push_back(t);
    }
  }
  static_assert(kTile == 2 * kSpan && kSpanPoints == 3, "span points assume 16-pixel tiles");
  span_rays_.assign(tiles_.size() * kTile * kSpanPoints * 2, 0.f);
  for (std::size_t i = 0; i < tiles_.size(); ++i) {
    const RenderTile& t = tiles_[i];
    float* out = span_rays_.data() + i * kTile * kSpanPoints * 2;
    for (int r = 0; r < t.y1 - t.y0; ++r) {
      for (int j = 0; j < kSpanPoints; ++j) {
        const std::size_t p = static_cast<std::size_t>(t.y0 + r) * static_cast<std::size_t>(w) + static_cast<std::size_t>(span_x(t, j));
        out[(r * kSpanPoints + j) * 2] = x_[p];
        out[(r * kSpanPoints + j) * 2 + 1] = y_[p];
      }
    }
  }
}

}  // namespace labo::sim
