#pragma once
// The "tello" section: the link (TelloLink), the emulator (TelloEmulator) and the Tello's camera,
// which replaces cameras.front whenever a Tello flies (serve --drone tello, emulate --protocol tello).
//
// The camera default: 960x720, the SDK stream's size, with the 82.6 deg field of view of the Tello's
// specification taken as the image's diagonal, no distortion: f = 600 / tan(41.3 deg) = 683 px,
// principal point at the centre. A default until the lab calibrates its drone (docs/tello.md).
// Sensors: a time-of-flight range to the surface below (the state's `tof`, the sample's altitude),
// a barometer (`baro`), an IMU; the Tello EDU's downward camera ("downvision 1": grey, 320x240)
// replaces cameras.bottom. Its default: 320x240 with the AR.Drone 2.0 bottom camera's field of view
// (fx = fy = 350 px, about 49 x 38 deg), centred, no distortion: the Tello's documents give no figure,
// a lab calibrates its drone. A plain Tello has no such camera: the link falls back (docs/tello.md).
#include "core/camera_config.hpp"
#include "drone/tello/tello_emulator.hpp"
#include "drone/tello/tello_link.hpp"

namespace labo::tello {

// The default above: 960x720, f = 683 px, centred, no distortion.
CameraIntrinsics tello_front_camera();
// The downward camera's default above: 320x240, f = 350 px, centred, no distortion.
CameraIntrinsics tello_downward_camera();

struct TelloConfig {
  TelloLinkSettings link;
  TelloEmulatorSettings emulator;
  CameraIntrinsics camera = tello_front_camera();
  CameraIntrinsics bottom_camera = tello_downward_camera();
};

// Reads {"link": {...}, "emulator": {...}, "camera": {width, height, fx, fy, cx, cy, distortion},
// "bottom_camera": {the same, 320x240 only: the downward camera's stream},
// "estimation": {...}}, every key optional; refuses unknown keys. "estimation" (the estimation
// section's keys, for a Tello's sensors: docs/tello.md) is only required to be an object here: the
// flight software's layers read it over the estimation section (server, bench).
TelloConfig read_tello_config(const ConfigReader& section);
// The config's "tello" section, or the defaults without one.
TelloConfig read_tello_config_of(const ConfigReader& root);

// `cameras` with the front and bottom cameras replaced by the Tello's.
CamerasConfig tello_cameras(const TelloConfig& tello, const CamerasConfig& cameras);

}  // namespace labo::tello
