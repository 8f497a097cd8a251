#include "localization/planar/planar_config.hpp"

#include <string>

namespace labo::planar {

const char* to_string(TrackerKind kind) { return kind == TrackerKind::Ecc ? "ecc" : "ic"; }

const char* to_string(PoseRefinement refinement) { return refinement == PoseRefinement::Se3 ? "se3" : "none"; }

const char* to_string(TemplateSearch search) { return search == TemplateSearch::CoarseToFine ? "coarse_to_fine" : "per_scale"; }

const char* to_string(NearDetector detector) {
  switch (detector) {
    case NearDetector::Sift: return "sift";
    case NearDetector::Orb: return "orb";
    case NearDetector::Brisk: return "brisk";
    case NearDetector::Akaze: return "akaze";
  }
  return "?";
}

namespace {
NearDetector near_detector_named(const std::string& name) {
  if (name == "orb") return NearDetector::Orb;
  if (name == "brisk") return NearDetector::Brisk;
  if (name == "akaze") return NearDetector::Akaze;
  return NearDetector::Sift;
}
}  // namespace

PlanarConfig read_planar_config(const ConfigReader& node) {
  PlanarConfig c;
  c.tracker = node.choice_or("tracker", "ic", {"ic", "ecc"}) == "ecc" ? TrackerKind::Ecc
                                                                     : TrackerKind::InverseCompositional;
  c.pose_refinement = node.choice_or("pose_refinement", "se3", {"se3", "none"}) == "se3" ? PoseRefinement::Se3
                                                                                      : PoseRefinement::None;
  c.se3.max_iterations = node.integer_or("se3_iterations", c.se3.max_iterations, 1, 100);
  c.se3.max_samples = node.integer_or("se3_max_samples", c.se3.max_samples, 100, 100000);
  c.se3.covariance_inflation =
      node.number_or("se3_covariance_inflation", c.se3.covariance_inflation, Range{0.0, 100.0, true});
  c.se3.smoothing_sigma_px = node.number_or("se3_smoothing_sigma_px", c.se3.smoothing_sigma_px, Range::closed(0.0, 3.0));
  c.se3.resample_to_frame =
      node.choice_or("se3_template_resolution", "pyramid", {"frame", "pyramid"}) == "frame";
  c.se3.estimate_blur = node.boolean_or("se3_estimate_blur", c.se3.estimate_blur);
  c.se3_footprint_model = node.choice_or("se3_pixel_model", "footprint", {"footprint", "sampled"}) == "footprint";
  c.se3_footprint_max_width_px =
      node.number_or("se3_footprint_max_width_px", c.se3_footprint_max_width_px, Range::positive());
  c.pyramid_levels = node.integer_or("pyramid_levels", c.pyramid_levels, 1, 5);
  c.max_iterations = node.integer_or("max_iterations", c.max_iterations, 1, 200);
  c.max_samples = node.integer_or("max_samples", c.max_samples, 100, 100000);
  c.convergence_px = node.number_or("convergence_px", c.convergence_px, Range{0.0, 1.0, true});
  c.ic_smoothing_sigma = node.number_or("ic_smoothing_sigma", c.ic_smoothing_sigma, Range::closed(0.0, 5.0));
  c.esm_iterations = node.integer_or("esm_iterations", c.esm_iterations, 0, 100);
  c.ecc_max_iterations = node.integer_or("ecc_max_iterations", c.ecc_max_iterations, 1, 1000);
  c.ecc_epsilon = node.number_or("ecc_epsilon", c.ecc_epsilon, Range{0.0, 1.0, true});
  c.ecc_gauss_size = node.integer_or("ecc_gauss_size", c.ecc_gauss_size, 1, 15);
  if (c.ecc_gauss_size % 2 == 0) node.fail("ecc_gauss_size", "must be odd (a Gaussian kernel size)");
  c.detection_min_width_fraction =
      node.number_or("detection_min_width_fraction", c.detection_min_width_fraction, Range{0.0, 1.0, true});
  c.detection_max_width_fraction =
      node.number_or("detection_max_width_fraction", c.detection_max_width_fraction, Range{0.0, 1.0, true});
  if (c.detection_max_width_fraction <= c.detection_min_width_fraction) {
    node.fail("detection_max_width_fraction", "must exceed detection_min_width_fraction");
  }
  c.detection_scale_step = node.number_or("detection_scale_step", c.detection_scale_step, Range{1.0, 2.0, true});
  c.template_search = node.choice_or("template_search", to_string(c.template_search), {"coarse_to_fine", "per_scale"}) == "per_scale"
                          ? TemplateSearch::PerScale
                          : TemplateSearch::CoarseToFine;
  c.detection_coarse_width_px = node.integer_or("detection_coarse_width_px", c.detection_coarse_width_px, 8, 128);
  c.detection_candidates = node.integer_or("detection_candidates", c.detection_candidates, 1, 8);
  c.detection_match_width_px = node.integer_or("detection_match_width_px", c.detection_match_width_px, 16, 256);
  c.near_detector = near_detector_named(node.choice_or("near_detector", to_string(c.near_detector), {"sift", "orb", "brisk", "akaze"}));
  c.near_frame_scale = node.number_or("near_frame_scale", c.near_frame_scale, Range::closed(0.25, 1.0));
  c.near_ratio = node.number_or("near_ratio", c.near_ratio, Range{0.0, 1.0, true});
  c.ransac_threshold_px = node.number_or("ransac_threshold_px", c.ransac_threshold_px, Range{0.0, 20.0, true});
  c.near_max_frame_features = node.integer_or("near_max_frame_features", c.near_max_frame_features, 50, 20000);
  c.min_visible_fraction = node.number_or("min_visible_fraction", c.min_visible_fraction, Range{0.0, 1.0, true});
  c.min_image_fraction = node.number_or("min_image_fraction", c.min_image_fraction, Range{0.0, 1.0, true});
  c.max_template_side_px = node.number_or("max_template_side_px", c.max_template_side_px, Range::closed(64, 2000));
  c.min_intensity_stddev = node.number_or("min_intensity_stddev", c.min_intensity_stddev, Range::non_negative());
  c.min_edge_fraction = node.number_or("min_edge_fraction", c.min_edge_fraction, Range::closed(0.0, 1.0));
  c.min_gradient_isotropy = node.number_or("min_gradient_isotropy", c.min_gradient_isotropy, Range::closed(0.0, 1.0));
  node.finish();
  return c;
}

}  // namespace labo::planar
