#include "core/camera_config.hpp"

namespace labo {

CameraIntrinsics read_camera_intrinsics(const ConfigReader& node) {
  CameraIntrinsics k;
  k.width = node.integer("width", 16, 8192);
  k.height = node.integer("height", 16, 8192);
  k.fx = node.number("fx", Range::positive());
  k.fy = node.number("fy", Range::positive());
  k.cx = node.number("cx", Range::closed(0, k.width));
  k.cy = node.number("cy", Range::closed(0, k.height));
  if (node.has("distortion")) {
    const auto d = node.numbers("distortion", 5, Range::closed(-10, 10));
    k.k1 = d[0];
    k.k2 = d[1];
    k.p1 = d[2];
    k.p2 = d[3];
    k.k3 = d[4];
  }
  k.calibration_error_px = node.number_or("calibration_error_px", 0.0, Range::closed(0, 50));
  node.finish();
  return k;
}

CamerasConfig read_cameras_config(const ConfigReader& node) {
  CamerasConfig c;
  c.front = read_camera_intrinsics(node.object("front"));
  c.bottom = read_camera_intrinsics(node.object("bottom"));
  node.finish();
  return c;
}

CamerasConfig ardrone2_cameras() {
  return {PinholeCamera::ardrone2_front().intrinsics(), PinholeCamera::ardrone2_bottom().intrinsics()};
}

CamerasConfig read_cameras_config_or_stock(const ConfigReader& root) {
  return root.has("cameras") ? read_cameras_config(root.object("cameras")) : ardrone2_cameras();
}

}  // namespace labo
