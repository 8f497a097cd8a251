#pragma once
#include "core/camera_model.hpp"
#include "core/config_reader.hpp"

namespace labo {

// Reads {"width", "height", "fx", "fy", "cx", "cy", "distortion": [k1, k2, p1, p2, k3]}.
CameraIntrinsics read_camera_intrinsics(const ConfigReader& node);

struct CamerasConfig {
  CameraIntrinsics front;
  CameraIntrinsics bottom;
};

// Reads {"front": {...}, "bottom": {...}}.
CamerasConfig read_cameras_config(const ConfigReader& node);

// The AR.Drone 2.0's stock calibration of both cameras (PinholeCamera::ardrone2_front/bottom).
CamerasConfig ardrone2_cameras();

// The "cameras" section of a configuration's root, or the AR.Drone 2.0's stock calibration without it.
CamerasConfig read_cameras_config_or_stock(const ConfigReader& root);

}  // namespace labo
