#include "drone/tello/tello_config.hpp"

#include <cmath>
#include <numbers>

#include "core/config_reader.hpp"

namespace labo {

namespace {
constexpr int kWidth = 960, kHeight = 720;
constexpr double kDiagonalFovDeg = 82.6;
}  // namespace

CameraIntrinsics tello_front_camera() {
  CameraIntrinsics k;
  k.width = kWidth;
  k.height = kHeight;
  const double half_diagonal_px = 0.5 * std::hypot(kWidth, kHeight);
  k.fx = k.fy = half_diagonal_px / std::tan(0.5 * kDiagonalFovDeg * std::numbers::pi / 180.0);
  k.cx = 0.5 * kWidth;
  k.cy = 0.5 * kHeight;
  return k;
}

TelloConfig read_tello_config(const ConfigReader& c) {
  TelloConfig t;
  if (c.has("link")) t.link = read_tello_link_settings(c.object("link"));
  if (c.has("emulator")) t.emulator = read_tello_emulator_settings(c.object("emulator"));
  if (c.has("camera")) t.camera = read_camera_intrinsics(c.object("camera"));
  // The estimator's settings for a Tello: the estimation section's keys, read over that section by
  // the layers that fly one (localization's read_estimation_config); here only an object is required.
  if (c.has("estimation")) c.object("estimation");
  c.finish();
  return t;
}

TelloConfig read_tello_config_of(const ConfigReader& root) {
  return root.has("tello") ? read_tello_config(root.object("tello")) : TelloConfig{};
}

CamerasConfig tello_cameras(const TelloConfig& tello, const CamerasConfig& cameras) {
  CamerasConfig c = cameras;
  c.front = tello.camera;
  return c;
}

}  // namespace labo
