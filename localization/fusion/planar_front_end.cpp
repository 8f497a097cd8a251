#include "localization/fusion/planar_front_end.hpp"

#include <stdexcept>

namespace labo::fusion {

namespace {
// Frames further apart than this: the last homography is no prior any more (the front-end was not
// in focus, or the camera switched), so the track starts over with a detection.
constexpr Seconds kMaxTrackingGapS = 0.5;
// The retry without the predicted distance may change the detector; a template match it finds farther
// from the prediction than this factor (the localizer's own template window around a predicted
// distance, planar_localizer.cpp) is a candidate, reported once the tracker has followed it for
// kConfirmFrames frames in a row: hysteresis on the detection. With the panel below the view after a
// push up, the retry's template matching finds other texture several metres beyond the panel with a
// high correlation; such tracks end in a pose jump within a few frames, and without the hysteresis
// each would be reported as the panel. A prediction that is wrong, with the panel really there, costs
// kConfirmFrames frames, not the panel. Tests "vision front-ends: a retried detection far from the
// predicted distance that the tracker loses never counts" and "vision front-ends: a wrong predicted
// distance costs the confirmation frames, not the target".
constexpr double kRetryScaleFactor = 1.6;
constexpr int kConfirmFrames = 15;

bool implausible_retry(const planar::PlanarResult& r, bool retried, std::optional<double> expected_m) {
  if (!retried || !expected_m || !(*expected_m > 0) || !r.has_pose || r.state != planar::PlanarState::Detected) return false;
  if (r.method != planar::PlanarMethod::TemplateMatching) return false;  // SIFT's inliers identify the panel at any scale
  const double ratio = r.distance_m / *expected_m;
  return ratio > kRetryScaleFactor || ratio < 1.0 / kRetryScaleFactor;
}

bool lost_track(const planar::PlanarResult& r) {
  return r.method == planar::PlanarMethod::Ecc || r.method == planar::PlanarMethod::InverseCompositional;
}

TrackState track_state_of(planar::PlanarState s) {
  switch (s) {
    case planar::PlanarState::Searching: return TrackState::Searching;
    case planar::PlanarState::Detected:
    case planar::PlanarState::Tracking: return TrackState::Tracking;
    case planar::PlanarState::Lost: return TrackState::Lost;
  }
  return TrackState::Lost;
}
}  // namespace

planar::PlanarTemplate load_target_template(const PlanarTarget& target, const planar::PlanarConfig& config) {
  if (target.template_path.empty())
    throw std::invalid_argument("planar target '" + target.id + "': no template image (the lab file's \"template\")");
  try {
    return planar::PlanarTemplate::load(target.template_path, target.width_m, target.height_m, config);
  } catch (const std::exception& e) {
    throw std::invalid_argument("planar target '" + target.id + "': " + e.what());
  }
}

PlanarFrontEnd::PlanarFrontEnd(const PlanarTarget& target, const PinholeCamera& camera, const VisionThresholds& vision,
                               const planar::PlanarConfig& config)
    : localizer_(load_target_template(target, config), camera,
                 planar::PlanarObjectThresholds::from(vision, target.sift_switch_distance_m, target.sift_min_inliers), config) {
  observation_.image_points.reserve(4);
}

void PlanarFrontEnd::reset() {
  localizer_.reset();
  confirming_ = -1;
  last_t_.reset();
  retry_without_distance_ = false;
  observation_.state = TrackState::Off;
}

const TargetObservation& PlanarFrontEnd::process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) {
  if (last_t_ && t - *last_t_ > kMaxTrackingGapS) {
    localizer_.reset();
    confirming_ = -1;
  }
  last_t_ = t;
  // The predicted distance picks one detector (the paper's lambda switch); when that found nothing,
  // the next frame runs both, so a wrong prediction or a detector that fails at this range (template
  // matching on a target filling the view) cannot keep the target unseen. A lost *track* is no failed
  // detection: the next frame detects with the prediction first. Were a lost track a retry too, a
  // template match that keeps finding the same false match (after a vertical push, at the standoff)
  // would lose and re-find it every other frame and SIFT, which finds the panel there, would not run.
  const bool retried = retry_without_distance_;
  const std::optional<double> distance = retried ? std::nullopt : expected_distance_m;
  result_ = localizer_.process(gray, t, distance);
  retry_without_distance_ = !result_.has_pose && distance.has_value() && !lost_track(result_);
  if (implausible_retry(result_, retried, expected_distance_m)) {
    confirming_ = 0;
  } else if (confirming_ >= 0) {
    const bool followed = result_.has_pose && result_.state == planar::PlanarState::Tracking;
    confirming_ = followed && confirming_ + 1 < kConfirmFrames ? confirming_ + 1 : -1;
  }
  const bool unconfirmed = confirming_ >= 0;
  TargetObservation& o = observation_;
  o.t = t;
  o.state = unconfirmed ? TrackState::Lost : track_state_of(result_.state);
  o.method = to_string(result_.method);
  o.reason = unconfirmed ? "unconfirmed_detection" : result_.has_pose ? "" : to_string(result_.reason);
  o.quality = result_.has_pose && !unconfirmed ? result_.quality : 0.0;
  o.rotation_sigma_rad = result_.has_pose && !unconfirmed ? result_.rotation_sigma_rad : 0.0;
  if (result_.has_pose && !unconfirmed) {
    o.T_cam_target = result_.T_cam_object;
    o.image_points.resize(4);
    for (std::size_t i = 0; i < 4; ++i)
      o.image_points[i] = cv::Point2f(static_cast<float>(result_.image_corners[i].x), static_cast<float>(result_.image_corners[i].y));
  } else {
    o.image_points.clear();
  }
  return o;
}

}  // namespace labo::fusion
