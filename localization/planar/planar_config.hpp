#pragma once
// Settings of the planar-object pipeline (config section "planar"). The paper's thresholds α, β, D,
// λ and N are not here: they live in the "vision" section (localization/vision_thresholds.hpp).
#include "core/config_reader.hpp"
#include "localization/planar/pose/se3_pose_refiner.hpp"

namespace labo::planar {

enum class TrackerKind { Ecc, InverseCompositional };
// How far detection searches (detect/template_detector.hpp).
enum class TemplateSearch { CoarseToFine, PerScale };
// The features of near detection (detect/planar_detectors.hpp).
enum class NearDetector { Sift, Orb, Brisk, Akaze };
// What follows IPPE: nothing, or the photometric 6-DoF refinement of se3_pose_refiner.hpp.
enum class PoseRefinement { None, Se3 };

const char* to_string(TrackerKind kind);
const char* to_string(PoseRefinement refinement);
const char* to_string(TemplateSearch search);
const char* to_string(NearDetector detector);

struct PlanarConfig {
  // Which frame-to-frame homography tracker runs: OpenCV's findTransformECC or LaboDrone's own
  // pyramidal inverse-compositional tracker (faster and wider basin in `labodrone-bench bench planar`).
  TrackerKind tracker = TrackerKind::InverseCompositional;

  // Own tracker.
  int pyramid_levels = 3;          // image levels used while tracking (coarse-to-fine)
  int max_iterations = 30;         // per level
  int max_samples = 1500;          // template pixels per level (highest gradient, spread over a grid)
  double convergence_px = 0.01;    // stop a level when no corner moves more than this (level-0 px)
  double ic_smoothing_sigma = 0.0; // Gaussian blur of the template levels (px), 0 = none
  int esm_iterations = 4;          // ESM iterations ending the finest level (0: pure IC)

  // Pose: IPPE on the tracker's corners, then (se3) the photometric refinement in SE(3), which fixes
  // the tilt of a panel seen face-on at range (docs/planar.md).
  PoseRefinement pose_refinement = PoseRefinement::Se3;
  // The refinement's own settings (config keys se3_iterations, se3_max_samples,
  // se3_covariance_inflation, se3_smoothing_sigma_px, se3_template_resolution "frame"|"pyramid",
  // se3_estimate_blur); its min_correlation is the vision section's alpha.
  Se3RefinerSettings se3{.max_samples = 1200};
  // How the refinement predicts the frame ("se3_pixel_model"): "footprint" (true) fits the raw frame's
  // pixels, each predicted as the template's mean over its footprint (AreaPoseRefiner), while the
  // panel's image is at most `se3_footprint_max_width_px` wide and no motion blur is modelled;
  // "sampled" (false): the template samples in the undistorted, smoothed frame (Se3PoseRefiner).
  bool se3_footprint_model = true;
  double se3_footprint_max_width_px = 1e9;

  // ECC (OpenCV).
  int ecc_max_iterations = 50;
  double ecc_epsilon = 1e-3;       // on the increase of the correlation coefficient
  int ecc_gauss_size = 5;

  // Far detection by template matching: the object's width in the image, as a fraction of the image
  // width, is searched from min to max in geometric steps. coarse_to_fine: every width matched on the
  // frame pyramid level where the template is about `detection_coarse_width_px` wide, the
  // `detection_candidates` best places again one level finer; per_scale: every width matched over the
  // whole image resized to where the template is `detection_match_width_px` wide.
  TemplateSearch template_search = TemplateSearch::CoarseToFine;
  double detection_min_width_fraction = 0.05;
  double detection_max_width_fraction = 0.80;
  double detection_scale_step = 1.15;
  int detection_coarse_width_px = 12;
  int detection_candidates = 4;
  int detection_match_width_px = 40;

  // Near detection by features: the paper's SIFT, or ORB, BRISK, AKAZE; on the frame resized by
  // `near_frame_scale`; Lowe's ratio test at `near_ratio`; at most `near_max_frame_features` in the
  // frame (SIFT and ORB).
  NearDetector near_detector = NearDetector::Orb;
  double near_frame_scale = 1.0;
  double near_ratio = 0.75;
  int near_max_frame_features = 1500;
  double ransac_threshold_px = 3.0;

  // Loss and quality.
  // A loss for too little in view (out_of_view) when less than min_visible_fraction of the panel's area
  // is inside the image and the part inside covers less than min_image_fraction of the image: an object
  // larger than the view (the platform below ~0.7 m) is tracked on the part that fills the image.
  double min_visible_fraction = 0.6;
  double min_image_fraction = 0.5;
  double max_template_side_px = 320;  // larger templates are downscaled for tracking

  // Texture test: a template is refused when its grey levels are nearly flat, when too few pixels
  // carry an edge, or when the edges all run one way (a stripe pattern cannot fix a homography).
  double min_intensity_stddev = 8.0;
  double min_edge_fraction = 0.02;
  double min_gradient_isotropy = 0.05;  // smaller / larger eigenvalue of the gradient structure tensor
};

// Reads {"tracker": "ic"|"ecc", "pose_refinement": "se3"|"none", "se3_iterations", "se3_max_samples",
// "se3_covariance_inflation", "se3_smoothing_sigma_px", "se3_template_resolution": "frame"|"pyramid", "se3_estimate_blur", "se3_pixel_model": "footprint"|"sampled", "se3_footprint_max_width_px", "pyramid_levels", "max_iterations", "max_samples", "convergence_px", "ic_smoothing_sigma", "esm_iterations",
// "ecc_max_iterations", "ecc_epsilon", "ecc_gauss_size", "detection_min_width_fraction",
// "detection_max_width_fraction", "detection_scale_step", "template_search": "coarse_to_fine"|"per_scale",
// "detection_coarse_width_px", "detection_candidates", "detection_match_width_px",
// "near_detector": "sift"|"orb"|"brisk"|"akaze", "near_frame_scale", "near_ratio", "ransac_threshold_px",
// "near_max_frame_features", "min_visible_fraction", "min_image_fraction", "max_template_side_px",
// "min_intensity_stddev", "min_edge_fraction", "min_gradient_isotropy"}; every key optional.
PlanarConfig read_planar_config(const ConfigReader& node);

}  // namespace labo::planar
