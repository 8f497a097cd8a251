#include "localization/slam/slam_settings.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::slam {

void validate_settings(const SlamSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("slam settings: " + what); };
  if (s.pyramid_levels != 4) fail("pyramid_levels must be 4");
  if (!(s.pyramid_scale >= 1.1 && s.pyramid_scale <= 2.5)) fail("pyramid_scale must be in [1.1, 2.5]");
  if (s.max_features < 100 || s.max_features > 5000) fail("max_features must be in [100, 5000]");
  if (s.max_points_searched < 50 || s.max_points_searched > 5000) fail("max_points_searched must be in [50, 5000]");
  if (s.fast_threshold < 5 || s.fast_threshold > 100) fail("fast_threshold must be in [5, 100]");
  if (!(s.smoothing_sigma_px >= 0 && s.smoothing_sigma_px <= 3)) fail("smoothing_sigma_px must be in [0, 3]");
  if (!(s.quality_lost > 0 && s.quality_lost < s.quality_good && s.quality_good < 1)) {
    fail("need 0 < quality_lost < quality_good < 1");
  }
  if (s.keyframe_min_points_dodgy < 0) fail("keyframe_min_points_dodgy must be >= 0 (0: keyframes from Good frames only)");
  if (s.lost_after_bad_frames < 1) fail("lost_after_bad_frames must be >= 1");
  if (s.local_ba_keyframes < 2) fail("local_ba_keyframes must be >= 2");
  if (s.local_ba_iterations < 1 || s.global_ba_iterations < 1) fail("local_ba_iterations and global_ba_iterations must be >= 1");
  if (s.init_min_points < 20) fail("init_min_points must be >= 20");
  if (!(s.init_min_parallax_px > 0)) fail("init_min_parallax_px must be > 0");
  if (!(s.init_min_parallax_deg > 0 && s.init_min_parallax_deg < 90)) fail("init_min_parallax_deg must be in (0, 90)");
  if (s.global_ba_max_keyframes < 3) fail("global_ba_max_keyframes must be >= 3");
  if (s.global_ba_every < 1) fail("global_ba_every must be >= 1");
  if (s.global_ba_fixed_keyframes < 1 || s.global_ba_fixed_keyframes > 10) fail("global_ba_fixed_keyframes must be in [1, 10]");
  if (!(s.gravity_sigma_deg >= 0 && s.gravity_sigma_deg <= 10)) fail("gravity_sigma_deg must be in [0, 10] (0: no gravity prior)");
  if (!(s.loop_min_gap_s > 0)) fail("loop_min_gap_s must be > 0");
}

ExtractorSettings extractor_settings(const SlamSettings& s) {
  return {.levels = s.pyramid_levels,
          .scale = s.pyramid_scale,
          .max_features = s.max_features,
          .fast_threshold = s.fast_threshold,
          .fast_threshold_low = 7,
          .cell_px = 40,
          .smoothing_sigma_px = s.smoothing_sigma_px};
}

InitializerSettings initializer_settings(const SlamSettings& s) {
  return {.min_parallax_px = s.init_min_parallax_px,
          .timeout_s = s.init_timeout_s,
          .search_radius_px = 30.0,
          .max_hamming = 60,
          .geometry = {.min_points = s.init_min_points,
                       .min_parallax_deg = s.init_min_parallax_deg,
                       .ransac_threshold_px = 1.5,
                       .homography_ratio = 0.45}};
}

TrackerSettings tracker_settings(const SlamSettings& s) {
  return {.levels = s.pyramid_levels,
          .level_scale = s.pyramid_scale,
          .max_points_searched = s.max_points_searched,
          .coarse_points = s.coarse_points,
          .coarse_radius_px = s.coarse_radius_px,
          .fine_radius_px = s.fine_radius_px,
          .max_hamming = 50,
          .local_keyframes = 10,
          .patch_refinement = s.patch_refinement};
}

MapperSettings mapper_settings(const SlamSettings& s) {
  MapperSettings m;
  m.threaded = s.mapping_mode == MappingMode::Threaded;
  m.levels = s.pyramid_levels;
  m.level_scale = s.pyramid_scale;
  m.local_ba_keyframes = s.local_ba_keyframes;
  m.local_ba_iterations = s.local_ba_iterations;
  m.global_ba_iterations = s.global_ba_iterations;
  m.global_ba = s.global_ba_when_idle;
  m.global_ba_max_keyframes = s.global_ba_max_keyframes;
  m.global_ba_every = s.global_ba_every;
  m.global_ba_fixed_keyframes = s.global_ba_fixed_keyframes;
  m.cull_points = s.cull_points;
  m.new_point_clearance_px = s.new_point_clearance_px;
  m.patch_refinement = s.patch_refinement;
  m.gravity_sigma_rad = s.gravity_sigma_deg * M_PI / 180.0;
  m.loop.enabled = s.loop_closure;
  m.loop.min_gap_s = s.loop_min_gap_s;
  m.loop.levels = s.pyramid_levels;
  m.loop.level_scale = s.pyramid_scale;
  return m;
}

}  // namespace labo::slam
