#include "localization/fusion/face_front_end.hpp"

#include <stdexcept>

#include "localization/fusion/lab_pipelines.hpp"

namespace labo::fusion {

namespace {
// Frames further apart than this (face-follow was off, or the camera switched): search afresh
// rather than around a face seen long ago.
constexpr Seconds kMaxTrackingGapS = 0.5;
constexpr int kLandmarks = 68;
}  // namespace

FaceFrontEnd::FaceFrontEnd(std::unique_ptr<face::FacePoseEstimator> estimator) : estimator_(std::move(estimator)) {
  if (!estimator_) throw std::invalid_argument("FaceFrontEnd: no face pose estimator");
  observation_.image_points.reserve(kLandmarks);
}

void FaceFrontEnd::reset() {
  estimator_->reset();
  last_t_.reset();
  observation_.state = TrackState::Off;
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
  if (last_t_ && t - *last_t_ > kMaxTrackingGapS) estimator_->reset();
  last_t_ = t;
  result_ = estimator_->process(gray, t);
  TargetObservation& o = observation_;
  o.t = t;
  o.state = result_.tracking() ? TrackState::Tracking : TrackState::Lost;
  o.method = face::to_string(estimator_->method());
  o.reason = result_.tracking() ? std::string_view() : face::to_string(result_.reason);
  o.quality = result_.tracking() ? result_.quality : 0.0;
  if (result_.tracking()) o.T_cam_target = result_.T_cam_face * flip_about_y();
  // The landmarks are drawn even when the pose was refused: the UI shows what was found.
  const Eigen::Matrix2Xd& lm = result_.landmarks;
  o.image_points.resize(static_cast<std::size_t>(lm.cols()));
  for (Eigen::Index i = 0; i < lm.cols(); ++i)
    o.image_points[static_cast<std::size_t>(i)] = cv::Point2f(static_cast<float>(lm(0, i)), static_cast<float>(lm(1, i)));
  return o;
}

}  // namespace labo::fusion
