#include "localization/slam/slam_config.hpp"

namespace labo::slam {

SlamSettings read_slam_settings(const ConfigReader& node) {
  SlamSettings s;
  s.mapping_mode = node.choice_or("mapping", "threaded", {"threaded", "synchronous"}) == "threaded" ? MappingMode::Threaded
                                                                                                    : MappingMode::Synchronous;
  s.max_features = node.integer_or("max_features", s.max_features, 100, 5000);
  s.fast_threshold = node.integer_or("fast_threshold", s.fast_threshold, 5, 100);
  s.max_points_searched = node.integer_or("max_points_searched", s.max_points_searched, 50, 5000);
  s.patch_refinement = node.boolean_or("patch_refinement", s.patch_refinement);
  s.smoothing_sigma_px = node.number_or("smoothing_sigma_px", s.smoothing_sigma_px, Range::closed(0.0, 3.0));
  s.quality_good = node.number_or("quality_good", s.quality_good, Range{0.0, 1.0, true});
  s.quality_lost = node.number_or("quality_lost", s.quality_lost, Range{0.0, 1.0, true});
  if (s.quality_lost >= s.quality_good) node.fail("quality_lost", "must be below quality_good");
  s.keyframe_min_interval_s = node.number_or("keyframe_min_interval_s", s.keyframe_min_interval_s, Range::closed(0.0, 10.0));
  s.keyframe_overlap_ratio = node.number_or("keyframe_overlap_ratio", s.keyframe_overlap_ratio, Range::closed(0.1, 0.95));
  s.keyframe_min_points_dodgy = node.integer_or("keyframe_min_points_dodgy", s.keyframe_min_points_dodgy, 0, 5000);
  s.max_keyframes = node.integer_or("max_keyframes", s.max_keyframes, 2, 2000);
  s.global_ba_when_idle = node.boolean_or("global_ba_when_idle", s.global_ba_when_idle);
  s.global_ba_max_keyframes = node.integer_or("global_ba_max_keyframes", s.global_ba_max_keyframes, 3, 2000);
  s.global_ba_every = node.integer_or("global_ba_every", s.global_ba_every, 1, 1000);
  s.local_ba_keyframes = node.integer_or("local_ba_keyframes", s.local_ba_keyframes, 2, 50);
  s.local_ba_iterations = node.integer_or("local_ba_iterations", s.local_ba_iterations, 1, 100);
  s.global_ba_iterations = node.integer_or("global_ba_iterations", s.global_ba_iterations, 1, 100);
  s.global_ba_fixed_keyframes = node.integer_or("global_ba_fixed_keyframes", s.global_ba_fixed_keyframes, 1, 10);
  s.cull_points = node.boolean_or("cull_points", s.cull_points);
  s.new_point_clearance_px = node.number_or("new_point_clearance_px", s.new_point_clearance_px, Range::closed(0.0, 10.0));
  s.loop_closure = node.boolean_or("loop_closure", s.loop_closure);
  s.loop_min_gap_s = node.number_or("loop_min_gap_s", s.loop_min_gap_s, Range::closed(1.0, 600.0));
  s.init_min_parallax_px = node.number_or("init_min_parallax_px", s.init_min_parallax_px, Range::closed(2.0, 200.0));
  s.init_min_parallax_deg = node.number_or("init_min_parallax_deg", s.init_min_parallax_deg, Range::closed(0.1, 20.0));
  s.gravity_sigma_deg = node.number_or("gravity_sigma_deg", s.gravity_sigma_deg, Range::closed(0.0, 10.0));
  s.gravity_in_tracking = node.boolean_or("gravity_in_tracking", s.gravity_in_tracking);
  node.finish();
  return s;
}

}  // namespace labo::slam
