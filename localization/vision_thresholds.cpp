#include "localization/vision_thresholds.hpp"

#include <numbers>

namespace labo {

VisionThresholds read_vision_thresholds(const ConfigReader& node) {
  VisionThresholds t;
  t.template_correlation_alpha = node.number_or("template_correlation_alpha", t.template_correlation_alpha,
                                                Range{0.0, 1.0, true});
  t.sift_min_inliers = node.integer_or("sift_min_inliers", t.sift_min_inliers, 10, 30);
  t.angle_jump_beta_rad = node.number_or("angle_jump_beta_deg", 15.0, Range{0.0, 90.0, true}) *
                          std::numbers::pi / 180.0;
  t.distance_jump_m = node.number_or("distance_jump_m", t.distance_jump_m, Range{0.0, 5.0, true});
  t.sift_switch_distance_m = node.number_or("sift_switch_distance_m", t.sift_switch_distance_m,
                                            Range::closed(1.0, 3.0));
  t.ultrasound_step_gamma_m = node.number_or("ultrasound_step_gamma_m", t.ultrasound_step_gamma_m,
                                             Range{0.0, 1.0, true});
  node.finish();
  return t;
}

}  // namespace labo
