#pragma once
// What the camera adds to the sharp image: motion blur over the shutter time, and the sensor's
// exposure gain and noise.
//
// Motion blur: for each 16x16 tile, the point its corners see (at their mean depth) is projected at the
// start and at the end of the exposure, the drone moving with SceneState's linear and angular velocity;
// the tile is then integrated along that displacement exactly: the sharp image is taken as a scene that
// is constant over each pixel's cell, which a pixel integrating its own area sees as the bilinear
// surface through the pixel values, and the blurred pixel is that surface's mean along the motion
// segment (its kernel: the segment's integral of the bilinear weights, exact per cell crossed). A
// sub-pixel motion therefore blurs by its true amount; zero motion is the identity. Tiles moving less
// than kMinMotion_px are copied as they are (docs/sim_rendering.md: why that threshold).
//
// Sensor: out = clamp(gain * in + noise), the noise read from precomputed Gaussian tables at an
// offset drawn from the seed, the frame's time and the camera, so a frame is a pure function of them.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "drone/sim/render_camera_rays.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo::sim {

class MotionBlur {
 public:
  // Motions shorter than this are not drawn: the largest change of any pixel is len / 8 of the
  // contrast across an edge (0.4 grey levels for a black-to-white edge at 1/64 px), below the 8-bit
  // weights' resolution (1/256) and the sensor noise.
  static constexpr float kMinMotion_px = 1.f / 64;
  // Longer motions are drawn this long (3200 px/s over a 10 ms shutter: beyond any flight).
  static constexpr float kMaxMotion_px = 32.f;
  // The kernel's reach from the pixel (px) and the largest number of taps: the segment crosses at most
  // 2 * kMaxMotion_px + 2 cell borders, each cell it crosses has 4 corners.
  static constexpr int kReach = static_cast<int>(kMaxMotion_px) / 2 + 1;
  static constexpr int kMaxTaps = 4 * (2 * static_cast<int>(kMaxMotion_px) + 3);

  // One tap of a tile's kernel: a pixel offset and its weight in 1/256 (a kernel's weights sum to 256).
  struct Tap {
    int dx = 0, dy = 0;
    std::uint32_t weight = 0;
  };
  // The kernel of a motion `m` (pixels over the exposure) into `taps`; returns the number of taps
  // (one tap (0, 0, 256) below kMinMotion_px).
  static int kernel(const Eigen::Vector2f& m, Tap (&taps)[kMaxTaps]);

  explicit MotionBlur(const CameraRays& rays);

  // Image motion of each tile over `shutter_s` centred on scene.t; returns the largest (pixels).
  float plan(const SceneState& scene, const Eigen::Isometry3d& T_body_cam, double shutter_s, const std::vector<float>& tile_depth);
  // Sets one tile's motion (pixels) instead of planning it from a scene; for tests.
  void set_tile_motion(int tile, const Eigen::Vector2f& m) { motion_[static_cast<std::size_t>(tile)] = m; }
  // Blurs `src` into `dst` (both width x height packed texels) along the planned motion.
  void apply(const std::uint32_t* src, std::uint32_t* dst) const;
  // The planned motion of a tile (pixels), for tests.
  Eigen::Vector2f tile_motion(int tile) const { return motion_[static_cast<std::size_t>(tile)]; }

 private:
  const CameraRays& rays_;
  std::vector<Eigen::Vector2f> motion_;
};

class SensorResponse {
 public:
  // `noise_sigma` in grey levels (0 for none).
  SensorResponse(unsigned seed, double noise_sigma);

  // Packed texels (width x height) to BGR with `gain` and, when `noise`, the noise of frame `frame_key`.
  void apply(const std::uint32_t* colour, int width, int height, double gain, bool noise, std::uint64_t frame_key,
             cv::Mat& bgr) const;

 private:
  std::uint64_t seed_hash_;
  std::vector<std::uint8_t> raise_, lower_;  // the positive and negative parts of Gaussian noise
};

// A frame's key for the noise: the time's bits and the camera.
std::uint64_t frame_key(Seconds t, CameraId camera);

}  // namespace labo::sim
