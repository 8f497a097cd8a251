#pragma once
// The paper's vision thresholds (§4.2, §6.1), defaults as published: template correlation α = 0.8,
// SIFT minimum inliers N (10-30), angle jump β = 15°, distance jump D = 0.30 m, SIFT switch distance
// λ (1-3 m, per object; this is the default), ultrasound step γ = 0.10 m.
#include "core/config_reader.hpp"

namespace labo {

struct VisionThresholds {
  double template_correlation_alpha = 0.8;
  int sift_min_inliers = 20;
  double angle_jump_beta_rad = 15.0 * 3.14159265358979323846 / 180.0;
  double distance_jump_m = 0.30;
  double sift_switch_distance_m = 2.0;
  double ultrasound_step_gamma_m = 0.10;
};

// Reads {"template_correlation_alpha", "sift_min_inliers", "angle_jump_beta_deg", "distance_jump_m",
// "sift_switch_distance_m", "ultrasound_step_gamma_m"}; every key optional, defaults above.
VisionThresholds read_vision_thresholds(const ConfigReader& node);

}  // namespace labo
