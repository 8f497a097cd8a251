#pragma once
// What the camera adds to the sharp image: motion blur over the shutter time, and the sensor's
// exposure gain and noise.
//
// Motion blur: for each 16x16 tile, the point its corners see (at their mean depth) is projected at the
// start and at the end of the exposure, the drone moving with SceneState's linear and angular velocity;
// the tile is then averaged along that displacement (a box filter of one tap per pixel of motion).
// Tiles moving less than a pixel are copied as they are.
//
// Sensor: out = clamp(gain * in + noise), the noise read from precomputed Gaussian tables at an
// offset drawn from the seed, the frame's time and the camera, so a frame is a pure function of them.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "drone/sim/render_camera_rays.hpp"
#include "drone/sim/scene_renderer.hpp"

namespace labo {

class MotionBlur {
 public:
  static constexpr int kMaxTaps = 32;

  explicit MotionBlur(const CameraRays& rays);

  // Image motion of each tile over `shutter_s` centred on scene.t; returns the largest (pixels).
  float plan(const SceneState& scene, const Eigen::Isometry3d& T_body_cam, double shutter_s, const std::vector<float>& tile_depth);
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

}  // namespace labo
