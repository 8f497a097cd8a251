#pragma once
// The rays of every pixel of a camera, computed once (lens distortion included) so that rendering a
// frame only rotates planes into the camera, never undistorts a pixel. A ray is (x, y, 1) in the
// camera frame: (x, y) are the pixel's undistorted normalized coordinates, and a point at depth z on
// it is z * (x, y, 1). Pixels are grouped in square tiles for coherence tests.
#include <vector>

#include "core/camera_model.hpp"

namespace labo {

struct RenderTile {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;   // pixels [x0, x1) x [y0, y1)
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;  // bounds of its rays' (x, y)
  int corner[4] = {0, 0, 0, 0};          // pixel indices of its corner pixels
  int centre = 0;                        // pixel index near its centre
};

class CameraRays {
 public:
  static constexpr int kTile = 16;

  // Throws std::invalid_argument when the lens cannot be inverted at some pixel (the distortion
  // model folds over inside the image).
  explicit CameraRays(const PinholeCamera& camera);

  const PinholeCamera& camera() const { return camera_; }
  int width() const { return camera_.width(); }
  int height() const { return camera_.height(); }
  const float* ray_x() const { return x_.data(); }
  const float* ray_y() const { return y_.data(); }
  const std::vector<RenderTile>& tiles() const { return tiles_; }
  int tiles_x() const { return tiles_x_; }
  int tiles_y() const { return tiles_y_; }
  // Largest |(x, y)| of any pixel: points farther off-axis can never appear in the image.
  float max_radius() const { return max_radius_; }
  // Radians per pixel at the image centre (for texture footprints).
  float pixel_angle() const { return pixel_angle_; }

 private:
  PinholeCamera camera_;
  std::vector<float> x_, y_;
  std::vector<RenderTile> tiles_;
  int tiles_x_ = 0, tiles_y_ = 0;
  float max_radius_ = 0;
  float pixel_angle_ = 0;
};

}  // namespace labo
