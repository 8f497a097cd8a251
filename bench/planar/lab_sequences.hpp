#pragma once
// The planar bench's sequences rendered by the simulated lab's LabRenderer (drone/sim/lab_renderer.hpp:
// room, benches, instruments and the platform ray traced through the AR.Drone 2.0's cameras, motion
// blur over the 10 ms shutter from the body's velocity and turn rate, sensor noise), objects and
// cameras of config/lab.json and config/default.json.
#include <string>

#include "bench/planar/planar_sequence.hpp"

namespace labo::bench {

// The oscilloscope approached in the front camera: 3 m -> 0.6 m with a lateral sway, a height wobble
// and a yaw wobble of the camera (150 frames).
PlanarSequence render_lab_approach(const std::string& name, double min_visible);

// The landing platform in the bottom camera while the drone comes down from 1.5 m above its top to
// 0.3 m and climbs back (240 frames, 8 s, up to 0.47 m/s vertically), swaying sideways by a tenth of
// its height, turning +-29 deg (up to 0.47 rad/s) and tilting +-3.4 deg. Below ~0.7 m the platform
// (0.60 m) overfills the image: at 0.3 m a sixth of it is in view. The platform's own lambda and N.
PlanarSequence render_lab_platform_pass(const std::string& name, double min_visible);

}  // namespace labo::bench
