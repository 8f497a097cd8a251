#include "localization/face/face_config.hpp"

#include <cmath>
#include <numbers>

#include "core/candide3.hpp"
#include "localization/face/landmark_detector.hpp"
#include "core/source_tree.hpp"

namespace labo::face {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? path : (base / path).lexically_normal();
}
}  // namespace

FaceConfig default_face_config() {
  FaceConfig c;
  c.shape_predictor = LandmarkDetector::default_path();
  c.model = Candide3Model::default_path();
  c.mapping = default_ibug68_mapping_path();
  c.people_dir = labo::source_root() / "config" / "face" / "people";
  return c;
}

FaceConfig read_face_config(const ConfigReader& node, const std::filesystem::path& base_dir) {
  FaceConfig c = default_face_config();
  if (node.has("shape_predictor")) c.shape_predictor = resolve(base_dir, node.string("shape_predictor"));
  if (node.has("model")) c.model = resolve(base_dir, node.string("model"));
  if (node.has("mapping")) c.mapping = resolve(base_dir, node.string("mapping"));
  if (node.has("people_dir")) c.people_dir = resolve(base_dir, node.string("people_dir"));
  c.teacher = node.string_or("teacher", "");
  c.interpupillary_distance_m = node.number_or("interpupillary_distance_mm", 63.0, Range::closed(40, 90)) / 1000.0;
  const std::string method = node.choice_or("pnp_method", "lm_tracking",
                                            {"epnp", "ransac_p3p", "epnp_lm", "ransac_p3p_lm", "lm_tracking"});
  c.solver.method = *parse_pnp_method(method);
  c.solver.tracking_max_rms_px = node.number_or("tracking_max_rms_px", c.solver.tracking_max_rms_px, Range::positive());
  c.solver.ransac.inlier_threshold_px =
      node.number_or("ransac_inlier_threshold_px", c.solver.ransac.inlier_threshold_px, Range::positive());
  c.solver.lm.huber_px = node.number_or("lm_huber_px", c.solver.lm.huber_px, Range::positive());
  c.box_from_landmarks = node.choice_or("tracking_box", "landmarks", {"landmarks", "detector"}) == "landmarks";
  c.upright_crop = node.boolean_or("upright_crop", c.upright_crop);
  c.yaw_widen_exponent = node.number_or("yaw_widen_exponent", c.yaw_widen_exponent, Range::closed(0, 2));
  c.far_side_yaw_rad = node.number_or("far_side_yaw_deg", 0.0, Range::closed(0, 90)) * kDeg;
  c.landmark_noise_weights = node.boolean_or("landmark_noise_weights", c.landmark_noise_weights);
  c.frontal_view = node.boolean_or("frontal_view", c.frontal_view);
  c.surface_landmarks = node.boolean_or("surface_landmarks", c.surface_landmarks);
  c.head_tracking = node.boolean_or("head_tracking", c.head_tracking);
  c.restart_unfit_tracked_frames = node.boolean_or("restart_unfit_tracked_frames", c.restart_unfit_tracked_frames);
  c.start_view_passes = node.integer_or("start_view_passes", c.start_view_passes, 1, 20);
  c.start_mirror_yaw_rad = node.number_or("start_mirror_yaw_deg", 0.0, Range::closed(0, 90)) * kDeg;
  c.redetect_every_n_frames = node.integer_or("redetect_every_n_frames", c.redetect_every_n_frames, 1, 1000);
  if (node.has("lost_search_scales")) c.lost_search_scales = node.numbers("lost_search_scales", -1, Range::closed(0.25, 3.0));
  if (c.lost_search_scales.empty()) node.fail("lost_search_scales", "needs at least one scale");
  c.detector.region_scale = node.number_or("search_region_scale", c.detector.region_scale, Range::closed(1.2, 5.0));
  c.detector.target_face_px = node.number_or("search_face_px", c.detector.target_face_px, Range::closed(80, 300));
  c.detector.adjust_threshold = node.number_or("detector_adjust_threshold", 0.0, Range::closed(-1.0, 2.0));
  c.shape_fit.regularisation = node.number_or("shape_regularisation", c.shape_fit.regularisation, Range::non_negative());
  c.frontal_max_angle_rad = node.number_or("frontal_max_angle_deg", 15.0, Range::closed(1, 45)) * kDeg;
  c.portrait_min_interocular_px =
      node.number_or("portrait_min_interocular_px", c.portrait_min_interocular_px, Range::closed(8, 500));
  if (node.has("depth_refinement")) {
    const ConfigReader d = node.object("depth_refinement");
    auto& D = c.depth_refinement;
    D.min_views = d.integer_or("min_views", D.min_views, 3, 100000);
    D.min_yaw_span_rad = d.number_or("min_yaw_span_deg", D.min_yaw_span_rad / kDeg, Range::closed(0, 120)) * kDeg;
    D.min_pitch_span_rad = d.number_or("min_pitch_span_deg", D.min_pitch_span_rad / kDeg, Range::closed(0, 120)) * kDeg;
    D.pixel_sigma_px = d.number_or("pixel_sigma_px", D.pixel_sigma_px, Range::positive());
    D.huber_px = d.number_or("huber_px", D.huber_px, Range::positive());
    D.prior_sigma_m = d.number_or("prior_mm", D.prior_sigma_m * 1000.0, Range::positive()) / 1000.0;
    D.landmark_prior_sigma_m = d.number_or("landmark_prior_mm", D.landmark_prior_sigma_m * 1000.0, Range::non_negative()) / 1000.0;
    D.max_iterations = d.integer_or("max_iterations", D.max_iterations, 1, 1000);
    D.max_rms_px = d.number_or("max_rms_px", D.max_rms_px, Range::positive());
    D.max_depth_change_m = d.number_or("max_depth_change_mm", D.max_depth_change_m * 1000.0, Range::closed(0.1, 30)) / 1000.0;
    d.finish();
  }
  if (node.has("limits")) {
    const ConfigReader l = node.object("limits");
    auto& L = c.limits;
    L.max_rms_per_interocular = l.number_or("max_rms_per_interocular", L.max_rms_per_interocular, Range::positive());
    L.max_yaw_rad = l.number_or("max_yaw_deg", 70.0, Range::closed(10, 90)) * kDeg;
    L.max_pitch_rad = l.number_or("max_pitch_deg", 50.0, Range::closed(10, 90)) * kDeg;
    L.max_start_yaw_rad = l.number_or("max_start_yaw_deg", L.max_start_yaw_rad / kDeg, Range::closed(5, 90)) * kDeg;
    L.min_distance_m = l.number_or("min_distance_m", L.min_distance_m, Range::positive());
    L.max_distance_m = l.number_or("max_distance_m", L.max_distance_m, Range::positive());
    L.border_margin_px = l.number_or("border_margin_px", L.border_margin_px, Range::non_negative());
    L.min_interocular_px = l.number_or("min_interocular_px", L.min_interocular_px, Range::positive());
    L.max_jump_m = l.number_or("max_jump_m", L.max_jump_m, Range::positive());
    L.max_turn_rad = l.number_or("max_turn_deg", 25.0, Range::closed(1, 180)) * kDeg;
    L.max_scale_change = l.number_or("max_scale_change", L.max_scale_change, Range::closed(0.01, 10));
    L.max_detector_misses = l.integer_or("max_detector_misses", L.max_detector_misses, 0, 100);
    if (L.min_distance_m >= L.max_distance_m) l.fail("min_distance_m", "must be smaller than max_distance_m");
    l.finish();
  }
  node.finish();
  return c;
}

}  // namespace labo::face
