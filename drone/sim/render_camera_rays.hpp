#pragma once
// The rays of every pixel of a camera, computed once (lens distortion included) so that rendering a
// frame only rotates planes into the camera, never undistorts a pixel. A ray is (x, y, 1) in the
// camera frame: (x, y) are the pixel's undistorted normalized coordinates, and a point at depth z on
// it is z * (x, y, 1). Pixels are grouped in square tiles for coherence tests.
#include <algorithm>
#include <vector>

#include "core/camera_model.hpp"

namespace labo::sim {

struct RenderTile {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;   // pixels [x0, x1) x [y0, y1)
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;  // bounds of its rays' (x, y)
  int centre = 0;                        // pixel index near its centre
};

class CameraRays {
 public:
  static constexpr int kTile = 16;
  // Each tile row is traced exactly at kSpanPoints pixels (x0, x0 + kSpan, x1 - 1) and interpolated
  // in between; their rays are stored tile by tile, so a tile reads 384 contiguous bytes of rays.
  static constexpr int kSpan = 8;
  static constexpr int kSpanPoints = 3;

  // Throws std::invalid_argument when the lens cannot be inverted at some pixel (the distortion
  // model folds over inside the image).
  explicit CameraRays(const PinholeCamera& camera);

  const PinholeCamera& camera() const { return camera_; }
  int width() const { return camera_.width(); }
  int height() const { return camera_.height(); }
  const float* ray_x() const { return x_.data(); }
  const float* ray_y() const { return y_.data(); }
  const std::vector<RenderTile>& tiles() const { return tiles_; }
  // The span points of a tile's rows: row r, point j at [(r * kSpanPoints + j) * 2 + {0: x, 1: y}].
  const float* span_rays(int tile) const { return span_rays_.data() + static_cast<std::size_t>(tile) * kTile * kSpanPoints * 2; }
  // The pixel column of span point j of a tile.
  static int span_x(const RenderTile& t, int j) { return j == 0 ? t.x0 : (j == 1 ? std::min(t.x0 + kSpan, t.x1 - 1) : t.x1 - 1); }
  int tiles_x() const { return tiles_x_; }
  int tiles_y() const { return tiles_y_; }
  // Largest |(x, y)| of any pixel: points farther off-axis can never appear in the image.
  float max_radius() const { return max_radius_; }
  // The extent of all pixels' (x, y): the camera's field is inside x in [min_x, max_x], y in [min_y, max_y].
  float min_x() const { return min_x_; }
  float max_x() const { return max_x_; }
  float min_y() const { return min_y_; }
  float max_y() const { return max_y_; }
  // Radians per pixel at the image centre (for texture footprints).
  float pixel_angle() const { return pixel_angle_; }

 private:
  PinholeCamera camera_;
  std::vector<float> x_, y_;
  std::vector<RenderTile> tiles_;
  std::vector<float> span_rays_;
  int tiles_x_ = 0, tiles_y_ = 0;
  float max_radius_ = 0;
  float min_x_ = 0, max_x_ = 0, min_y_ = 0, max_y_ = 0;
  float pixel_angle_ = 0;
};

}  // namespace labo::sim
