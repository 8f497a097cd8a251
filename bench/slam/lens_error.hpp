#pragma once
// A lens model off the one the images were rendered with, as a drone's camera is off the calibration
// shared by its model (the randomized world draws the focal length within 3 %, the principal point
// within 5 px and k1, k2 within 0.03): `bench slam --lens-error` gives SLAM this model while the lab
// is rendered through the configured one.
#include <string>

#include "core/camera_model.hpp"

namespace labo::bench {

struct LensError {
  double focal_fraction = 0;  // fx and fy times 1 + this
  double principal_px = 0;    // added to cx and cy
  double k1 = 0, k2 = 0;      // added to the radial distortion
};

// "F,C,K1,K2" (four numbers); throws UsageError naming what is wrong: not four numbers, or one out of
// range (|F| <= 0.2, |C| <= 50 px, |K1|, |K2| <= 0.5).
LensError parse_lens_error(const std::string& text);

PinholeCamera with_lens_error(const PinholeCamera& camera, const LensError& error);

}  // namespace labo::bench
