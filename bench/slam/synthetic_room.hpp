#pragma once
// SyntheticRoom: a quick, self-contained renderer for SLAM tests and the benchmark until the sim
// engineer's renderer is merged: a box-shaped room whose walls, floor and ceiling carry procedural
// textures (shapes and lettering, seeded), plus one instrument panel on a wall with a finer texture.
// Each pixel's ray (through the real, distorted lens) is intersected with the box; textures are
// mip-mapped so that far walls do not alias. Sensor noise is added with a seeded generator.
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera_model.hpp"

namespace labo::bench {

struct SyntheticRoomSpec {
  Eigen::Vector3d min_corner{0, 0, 0};
  Eigen::Vector3d max_corner{8, 6, 3};
  double texel_m = 0.005;
  // Instrument panel on the wall x = max: centre (y, z) and size (m).
  Eigen::Vector2d panel_center_yz{3.0, 1.3};
  Eigen::Vector2d panel_size{0.5, 0.35};
  double panel_texel_m = 0.001;
  double noise_sigma = 2.0;  // grey levels
  unsigned seed = 7;
};

class SyntheticRoom {
 public:
  SyntheticRoom(const PinholeCamera& camera, const SyntheticRoomSpec& spec = {});
  // 8-bit grey image seen from T_world_cam (OpenCV camera axes).
  cv::Mat render(const Eigen::Isometry3d& T_world_cam, unsigned frame_seed = 0) const;
  const SyntheticRoomSpec& spec() const { return spec_; }
  // Centre of the instrument panel in the world, and its normal (into the room).
  Eigen::Vector3d panel_center() const;

 private:
  struct Texture {
    std::vector<cv::Mat> mips;  // CV_32F
    double texel_m;
  };
  float sample(const Texture& t, double u_m, double v_m, double footprint_m) const;

  PinholeCamera camera_;
  SyntheticRoomSpec spec_;
  std::array<Texture, 6> faces_;  // x-, x+, y-, y+, z- (floor), z+ (ceiling)
  Texture panel_;
  std::vector<Eigen::Vector3f> rays_;  // unit rays per pixel, camera frame
};

}  // namespace labo::bench
