#pragma once
// Localization of one planar object (an instrument's front panel in the front camera, the landing
// platform in the bottom camera) after the paper's Fig. 3:
//   searching/lost -> detection: features (the paper's SIFT; ORB by default, PlanarConfig::near_detector)
//   when the object is nearer than lambda, template matching on a pyramid otherwise (both, template
//   first, when the distance is unknown); the detection's
//   homography is refined by the tracker and accepted when the correlation exceeds alpha;
//   tracking -> the previous homography is the prior of the tracker (ECC or LaboDrone's IC) in the
//   next frame; the pose comes from IPPE on the tracker's corners, refined photometrically in SE(3)
//   (se3_pose_refiner.hpp) when configured; loss on no convergence, correlation below alpha, too little of the panel in view,
//   or a camera motion of more than D or a turn of more than beta since the previous frame (after
//   resolving the IPPE ambiguity, planar_pose.hpp). The frame after a loss runs detection again.
// Frames are undistorted first (precomputed maps, same K), so homographies are exact perspective
// maps; the reported corners are in the raw frame. Steady-state tracking with the IC tracker
// allocates nothing (tests/control/front_end_allocation_test.cpp; OpenCV's ECC allocates inside every
// call): IPPE, undistortion, pyramid and smoothing are LaboDrone's own (ippe.hpp, image_ops.hpp).
#include <memory>
#include <optional>

#include "core/camera_model.hpp"
#include "localization/planar/pose/area_pose_refiner.hpp"
#include "localization/planar/track/homography_tracker.hpp"
#include "localization/planar/image_ops.hpp"
#include "localization/planar/planar_config.hpp"
#include "localization/planar/detect/planar_detectors.hpp"
#include "localization/planar/detect/template_detector.hpp"
#include "localization/planar/pose/planar_pose.hpp"
#include "localization/planar/planar_result.hpp"
#include "localization/planar/planar_template.hpp"
#include "localization/planar/pose/se3_pose_refiner.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::planar {

struct PlanarObjectThresholds {
  double min_correlation = 0.8;           // alpha
  double max_jump_m = 0.30;               // D
  double max_turn_rad = 15.0 * 3.14159265358979 / 180.0;  // beta
  double sift_switch_distance_m = 2.0;    // lambda (per object): features nearer, template matching farther
  int sift_min_inliers = 20;              // N (per object): the near detection's minimum RANSAC inliers

  // From the "vision" section, with the object's own lambda and N when it has them.
  static PlanarObjectThresholds from(const VisionThresholds& vision, std::optional<double> lambda_m = {},
                                     std::optional<int> min_inliers = {});
};

class PlanarObjectLocalizer {
 public:
  PlanarObjectLocalizer(PlanarTemplate planar_template, const PinholeCamera& camera,
                        const PlanarObjectThresholds& thresholds, const PlanarConfig& config);

  // `gray` is the camera's CV_8UC1 frame. `predicted_distance_m` (from the state estimator) chooses
  // the detector and narrows the template-matching scales; without it the last pose's distance is
  // used while recent, else both detectors run.
  PlanarResult process(const cv::Mat& gray, Seconds t, std::optional<double> predicted_distance_m = {});
  // Forget the track (the next frame runs detection).
  void reset();

  const PlanarTemplate& planar_template() const { return template_; }
  const PinholeCamera& camera() const { return camera_; }
  TrackerKind tracker_kind() const { return tracker_->kind(); }

 private:
  PlanarResult track(const cv::Mat& image, PlanarResult r);
  PlanarResult detect(const cv::Mat& image, PlanarResult r, std::optional<double> distance_m);
  // Checks an aligned homography and fills the pose; returns the loss reason (None when accepted).
  PlanarLoss accept(const cv::Mat& image, const cv::Matx33d& H_working, double correlation, bool check_jump,
                    PlanarResult& r);
  // The SE(3) refinement of the IPPE pose when configured; fills the result's uncertainties. False
  // when the fit contradicts the tracker's homography (Se3Refinement::contradicts_start): the frame is
  // then a loss, not an unverified pose.
  bool refine_pose(const cv::Mat& image, PlanarPose& pose, double size_px, double margin, PlanarResult& r);
  // The SE(3) refinement of T_start, with the motion blur (if the panel moved fast) that fits best.
  // The exposure chosen last (index into the tried fractions, -1: none) is tried first: under auto
  // exposure it changes slowly, and the search then needs fewer refinements.
  // The panel centre's image motion since the last pose (zero when that is older than
  // kMaxBlurIntervalS): what the motion blur search models.
  Eigen::Vector2d panel_motion_px(const Eigen::Isometry3d& T, Seconds t) const;
  Se3Refinement refine_with_blur_search(const Eigen::Isometry3d& T_start, Seconds t, bool use_footprint, Eigen::Vector2d& blur_px,
                                        int& iterations);
  const cv::Mat& undistort(const cv::Mat& gray);
  // Object-frame x, y (m) of undistorted image points on the panel.
  std::array<Eigen::Vector2d, 4> object_points(const cv::Matx33d& H_working, const std::array<cv::Point2d, 4>& image_points) const;
  // One refinement of T_start: the footprint model on the raw frame when configured, no motion blur is
  // modelled and the panel is narrow enough (`use_footprint`), else Se3PoseRefiner on smoothed_.
  Se3Refinement refine_once(const Eigen::Isometry3d& T_start, bool use_footprint, const Eigen::Vector2d& blur_px = Eigen::Vector2d::Zero(),
                            const Eigen::Isometry3d* warm_start = nullptr) const;

  PlanarTemplate template_;
  PinholeCamera camera_;
  PlanarObjectThresholds thresholds_;
  PlanarConfig config_;
  std::unique_ptr<HomographyTracker> tracker_;
  TemplateMatchDetector template_detector_;
  FeatureMatchDetector feature_detector_;
  PlanarPoseSolver pose_solver_;
  Se3PoseRefiner pose_refiner_;
  std::optional<AreaPoseRefiner> footprint_refiner_;  // se3_pixel_model "footprint"
  LinearRemap8u undistortion_;          // precomputed undistortion (empty without distortion)
  cv::Mat undistorted_;                 // its reused output
  cv::Mat raw_;                         // the frame being processed, as it came (a header)
  Se3PoseRefiner::SmoothedFrame smoothed_;  // reused by the pose refinement

  bool tracking_ = false;
  bool ever_found_ = false;
  cv::Matx33d H_working_ = cv::Matx33d::eye();  // last accepted, working template px -> undistorted px
  std::optional<Eigen::Isometry3d> last_pose_;
  Seconds last_pose_t_ = 0;
  bool detection_confirmed_ = false;  // the frame after the detection was tracked
  int last_exposure_ = -1;  // see refine_with_blur_search
  // The IPPE pose of the last frame whose photometric fit contradicted the tracker (a loss): not a
  // pose to report, but good enough to measure the panel's image motion from, so that the next frame
  // can model its motion blur (a detection on a smeared frame has no other reference).
  std::optional<Eigen::Isometry3d> unverified_pose_;
  Seconds unverified_pose_t_ = 0;
};

}  // namespace labo::planar
