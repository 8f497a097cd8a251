#include "localization/fusion/face_front_end.hpp"

#include <stdexcept>

#include "localization/fusion/lab_pipelines.hpp"

namespace labo::fusion {

namespace {
// Frames further apart than this (the video link dropped, face-follow was off, or the camera
// switched): the face is searched for afresh rather than around where it was seen.
constexpr Seconds kMaxTrackingGapS = 0.5;
constexpr int kLandmarks = 68;

const face::FacePoseEstimator& checked(const std::unique_ptr<face::FacePoseEstimator>& estimator) {
  if (!estimator) throw std::invalid_argument("FaceFrontEnd: no face pose estimator");
  return *estimator;
}
}  // namespace

FaceFrontEnd::FaceFrontEnd(std::unique_ptr<face::FacePoseEstimator> estimator)
    : estimator_(std::move(estimator)), head_tracker_(checked(estimator_).camera()) {
  observation_.image_points.reserve(kLandmarks);
}

void FaceFrontEnd::reset() {
  estimator_->reset();
  head_tracker_.reset();
  head_.reset();
  last_t_.reset();
  observation_.state = TrackState::Off;
}

std::string_view FaceFrontEnd::lost_reason() const {
  // No face in the image after a followed head was lost: why the head was lost says more.
  const face::HeadLostReason head = head_tracker_.lost_reason();
  const bool head_was_followed = head != face::HeadLostReason::None && head != face::HeadLostReason::NotLearnt;
  if (!head_ && result_.reason == face::FaceLostReason::NoFace && head_was_followed) return face::to_string(head);
  return face::to_string(result_.reason);
}

void FaceFrontEnd::follow(const face::PersonShape& person) {
  std::lock_guard lock(pending_mutex_);
  pending_person_ = person;
}

const TargetObservation& FaceFrontEnd::process(const cv::Mat& gray, Seconds t, std::optional<double>) {
  {
    std::lock_guard lock(pending_mutex_);
    if (pending_person_) {
      estimator_->set_person(*pending_person_, true);
      estimator_->reset();
      pending_person_.reset();
    }
  }
  if (last_t_ && t - *last_t_ > kMaxTrackingGapS) {
    estimator_->reset();
    // A followed head is looked for again round where it was: a Wi-Fi outage of half a second (a
    // few every minute in the randomized world) otherwise loses the teacher to a search.
    head_tracker_.interrupt(t);
  }
  last_t_ = t;
  // Where the head was followed last frame is where a face turning back will be.
  if (head_) estimator_->search_near(head_->box);
  result_ = estimator_->process(gray, t);
  head_.reset();
  if (estimator_->config().head_tracking) {
    if (result_.tracking()) head_tracker_.learn(gray, result_.T_cam_face, t);
    else head_ = head_tracker_.follow(gray, t);
  }
  TargetObservation& o = observation_;
  o.t = t;
  o.state = result_.tracking() || head_ ? TrackState::Tracking : TrackState::Lost;
  o.position_only = !result_.tracking() && head_.has_value();
  o.method = o.position_only ? std::string("head") : face::to_string(estimator_->method());
  o.reason = result_.tracking() ? std::string_view() : lost_reason();
  o.quality = result_.tracking() ? result_.quality : head_ ? head_->score : 0.0;
  if (result_.tracking()) {
    o.T_cam_target = result_.T_cam_face * flip_about_y();
    R_cam_target_ = o.T_cam_target.linear();
  } else if (head_) {
    // The head's centre: the face is on the side it is turned to, which the head does not tell (a
    // teacher turned away has their face 0.18 m farther than one facing the drone).
    o.T_cam_target.linear() = R_cam_target_;
    o.T_cam_target.translation() = head_->p_cam_head_m;
  }
  if (o.position_only) {
    // The head's box corners: the UI draws the followed head, not landmarks that were refused.
    const cv::Rect2d& b = head_->box;
    o.image_points.assign({cv::Point2f(float(b.x), float(b.y)), cv::Point2f(float(b.x + b.width), float(b.y)),
                           cv::Point2f(float(b.x + b.width), float(b.y + b.height)), cv::Point2f(float(b.x), float(b.y + b.height))});
    return o;
  }
  // The landmarks are drawn even when the pose was refused: the UI shows what was found.
  const Eigen::Matrix2Xd& lm = result_.landmarks;
  o.image_points.resize(static_cast<std::size_t>(lm.cols()));
  for (Eigen::Index i = 0; i < lm.cols(); ++i)
    o.image_points[static_cast<std::size_t>(i)] = cv::Point2f(static_cast<float>(lm(0, i)), static_cast<float>(lm(1, i)));
  return o;
}

}  // namespace labo::fusion
