#include "control/planar_front_end.hpp"

#include <stdexcept>

namespace labo {

namespace {
// Frames further apart than this: the last homography is no prior any more (the front-end was not
// in focus, or the camera switched), so the track starts over with a detection.
constexpr Seconds kMaxTrackingGapS = 0.5;

TrackState track_state_of(PlanarState s) {
  switch (s) {
    case PlanarState::Searching: return TrackState::Searching;
    case PlanarState::Detected:
    case PlanarState::Tracking: return TrackState::Tracking;
    case PlanarState::Lost: return TrackState::Lost;
  }
  return TrackState::Lost;
}
}  // namespace

PlanarTemplate load_target_template(const PlanarTarget& target, const PlanarConfig& config) {
  if (target.template_path.empty())
    throw std::invalid_argument("planar target '" + target.id + "': no template image (the lab file's \"template\")");
  try {
    return PlanarTemplate::load(target.template_path, target.width_m, target.height_m, config);
  } catch (const std::exception& e) {
    throw std::invalid_argument("planar target '" + target.id + "': " + e.what());
  }
}

PlanarFrontEnd::PlanarFrontEnd(const PlanarTarget& target, const PinholeCamera& camera, const VisionThresholds& vision,
                               const PlanarConfig& config)
    : localizer_(load_target_template(target, config), camera,
                 PlanarObjectThresholds::from(vision, target.sift_switch_distance_m, target.sift_min_inliers), config) {
  observation_.image_points.reserve(4);
}

void PlanarFrontEnd::reset() {
  localizer_.reset();
  last_t_.reset();
  retry_without_distance_ = false;
  observation_.state = TrackState::Off;
}

const TargetObservation& PlanarFrontEnd::process(const cv::Mat& gray, Seconds t, std::optional<double> expected_distance_m) {
  if (last_t_ && t - *last_t_ > kMaxTrackingGapS) localizer_.reset();
  last_t_ = t;
  // The predicted distance picks one detector (the paper's lambda switch); when that found nothing,
  // the next frame runs both, so a wrong prediction or a detector that fails at this range (template
  // matching on a target filling the view) cannot keep the target unseen.
  const std::optional<double> distance = retry_without_distance_ ? std::nullopt : expected_distance_m;
  result_ = localizer_.process(gray, t, distance);
  retry_without_distance_ = !result_.has_pose && distance.has_value();
  TargetObservation& o = observation_;
  o.t = t;
  o.state = track_state_of(result_.state);
  o.method = to_string(result_.method);
  o.reason = result_.has_pose ? "" : to_string(result_.reason);
  o.quality = result_.has_pose ? result_.quality : 0.0;
  if (result_.has_pose) {
    o.T_cam_target = result_.T_cam_object;
    o.image_points.resize(4);
    for (std::size_t i = 0; i < 4; ++i)
      o.image_points[i] = cv::Point2f(static_cast<float>(result_.image_corners[i].x), static_cast<float>(result_.image_corners[i].y));
  } else {
    o.image_points.clear();
  }
  return o;
}

}  // namespace labo
