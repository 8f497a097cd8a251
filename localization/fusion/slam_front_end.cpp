#include "localization/fusion/slam_front_end.hpp"

#include <stdexcept>

namespace labo::fusion {

SlamState slam_state_of(slam::TrackingState state) {
  switch (state) {
    case slam::TrackingState::Initializing: return SlamState::Initializing;
    case slam::TrackingState::Good: return SlamState::Good;
    case slam::TrackingState::Dodgy: return SlamState::Dodgy;
    case slam::TrackingState::Lost: return SlamState::Lost;
  }
  return SlamState::Lost;
}

SlamSystemFrontEnd::SlamSystemFrontEnd(std::unique_ptr<slam::SlamSystem> slam) : slam_(std::move(slam)) {
  if (!slam_) throw std::invalid_argument("SlamSystemFrontEnd: no SLAM system");
}

void SlamSystemFrontEnd::restart_map() {
  slam_->reset();
  ++frame_.map_id;
  frame_.has_pose = false;
  frame_.summary = SlamSummary{};
}

bool SlamSystemFrontEnd::sample_map_points(Seconds t, std::vector<Eigen::Vector3d>& out) {
  if (points_sampled_t_ && t - *points_sampled_t_ < kMapPointsPeriodS && t >= *points_sampled_t_) return false;
  points_sampled_t_ = t;
  slam_->sample_points(out, kMaxMapPoints);
  return true;
}

const SlamFrame& SlamSystemFrontEnd::pause() {
  frame_.has_pose = false;
  frame_.summary.state = SlamState::Off;
  frame_.summary.points_found = frame_.summary.points_attempted = 0;
  return frame_;
}

const SlamFrame& SlamSystemFrontEnd::process(const cv::Mat& gray, Seconds t,
                                             const std::optional<Eigen::Isometry3d>& prior_T_cam_map,
                                             const std::optional<Eigen::Vector3d>& gravity_down_cam) {
  std::optional<slam::GravityMeasurement> gravity;
  if (gravity_down_cam) gravity = slam::GravityMeasurement{t, *gravity_down_cam};
  result_ = slam_->track(gray, t, prior_T_cam_map, gravity);
  SlamSummary& s = frame_.summary;
  s.state = slam_state_of(result_.state);
  s.points_found = result_.points_found;
  s.points_attempted = result_.points_attempted;
  frame_.has_pose = result_.T_cam_map.has_value() &&
                    (result_.state == slam::TrackingState::Good || result_.state == slam::TrackingState::Dodgy);
  if (frame_.has_pose) frame_.T_map_cam = result_.T_cam_map->inverse();
  // The map's size changes only with keyframes; status() copies the map's points, so it is read
  // then and not on every frame.
  if (result_.keyframe_added || result_.relocalized) {
    const slam::SlamStatus status = slam_->status();
    s.keyframes = status.keyframes;
    s.map_points = status.map_points;
    s.map_bytes = status.map_bytes;
  }
  return frame_;
}

}  // namespace labo::fusion
