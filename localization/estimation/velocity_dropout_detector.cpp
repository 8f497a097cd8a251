#include "localization/estimation/velocity_dropout_detector.hpp"

#include <algorithm>

namespace labo {

void VelocityDropoutDetector::reset() {
  head_ = size_ = 0;
  in_dropout_ = false;
  dropout_start_ = 0;
  onset_votes_ = resume_votes_ = 0;
  correction_ = {};
}

std::size_t VelocityDropoutDetector::first_at_or_after(Seconds t) const {
  std::size_t lo = 0, hi = size_;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (at(mid).t < t) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

Eigen::Vector2d VelocityDropoutDetector::mean_measured(std::size_t from, std::size_t to) const {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::size_t i = from; i <= to; ++i) sum += at(i).measured;
  return sum / static_cast<double>(to - from + 1);
}

VelocityDropoutDetector::Consistency VelocityDropoutDetector::consistency(Start from) {
  Consistency c;
  if (size_ < 2) return c;
  const Seconds now = at(size_ - 1).t;
  // At least half a window of history (after a reset, or a navdata gap that emptied nothing).
  if (at(0).t > now - 0.5 * settings_.window_s) return c;
  const std::size_t start = first_at_or_after(now - settings_.window_s);
  if (start + 1 >= size_) return c;
  const std::size_t start_end = std::max(start, first_at_or_after(at(start).t + settings_.average_s) - 1);
  const std::size_t end_begin = std::max(start + 1, first_at_or_after(now - settings_.average_s));
  if (start_end >= end_begin) return c;
  // The model from the window's start: v' = thrust - drag v, with each packet's measured tilt.
  Eigen::Vector2d v = from == Start::Measured ? mean_measured(start, start_end) : at(start).filter;
  model_velocity_[start] = v;
  for (std::size_t i = start + 1; i < size_; ++i) {
    const double dt = at(i).t - at(i - 1).t;
    v += (at(i - 1).thrust_accel - model_.drag_per_s * v) * dt;
    model_velocity_[i] = v;
  }
  Eigen::Vector2d model_end = Eigen::Vector2d::Zero();
  for (std::size_t i = end_begin; i < size_; ++i) model_end += model_velocity_[i];
  model_end /= static_cast<double>(size_ - end_begin);
  c.valid = true;
  c.measured_speed = mean_measured(end_begin, size_ - 1).norm();
  c.model_speed = model_end.norm();
  return c;
}

void VelocityDropoutDetector::take_back(std::size_t start) {
  // model_velocity_ holds the model over the window (consistency() of this packet); the filter fused
  // the failing measurements meanwhile. Its velocity becomes the model's, and it moves by what the
  // model would have moved more.
  correction_ = {};
  for (std::size_t i = start + 1; i < size_; ++i) {
    const double dt = at(i).t - at(i - 1).t;
    correction_.position += 0.5 * ((model_velocity_[i] - at(i).filter) + (model_velocity_[i - 1] - at(i - 1).filter)) * dt;
  }
  correction_.velocity = model_velocity_[size_ - 1] - at(size_ - 1).filter;
}

VelocityVerdict VelocityDropoutDetector::process(Seconds t, const Eigen::Vector2d& measured_world,
                                                 const Eigen::Vector2d& thrust_accel_world,
                                                 const Eigen::Vector2d& filter_velocity) {
  if (size_ > 0 && t < at(size_ - 1).t) reset();  // time went back: a new flight
  if (size_ == kCapacity) {
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
  Entry& e = ring_[(head_ + size_) % kCapacity];
  e = {t, measured_world, thrust_accel_world, filter_velocity};
  ++size_;

  VelocityVerdict verdict;
  const Consistency c = consistency(in_dropout_ ? Start::Measured : Start::Filter);
  if (!in_dropout_) {
    const bool lost = c.valid && c.model_speed - c.measured_speed > settings_.onset_mps &&
                      c.measured_speed < settings_.onset_ratio * c.model_speed;
    onset_votes_ = lost ? onset_votes_ + 1 : 0;
    if (onset_votes_ >= settings_.confirm_packets) {
      // The filter's velocity in the window's entries: e.filter of this packet is its prediction.
      take_back(first_at_or_after(t - settings_.window_s));
      in_dropout_ = true;
      dropout_start_ = t;
      onset_votes_ = resume_votes_ = 0;
      verdict.onset = true;
      verdict.fuse = false;
    }
    return verdict;
  }
  const std::size_t recent = std::max<std::size_t>(1, first_at_or_after(t - settings_.average_s));
  const Eigen::Vector2d measured_now = mean_measured(std::min(recent, size_ - 1), size_ - 1);
  const bool alive = c.valid && c.measured_speed > settings_.alive_mps &&
                     c.measured_speed > c.model_speed - settings_.onset_mps;
  const bool agrees = (measured_now - filter_velocity).norm() < settings_.agree_mps;
  resume_votes_ = (alive || agrees) ? resume_votes_ + 1 : 0;
  if (resume_votes_ >= settings_.confirm_packets) {
    in_dropout_ = false;
    onset_votes_ = resume_votes_ = 0;
    verdict.resumed = true;
    return verdict;
  }
  verdict.fuse = false;
  return verdict;
}

void VelocityDropoutDetector::record_filter_velocity(const Eigen::Vector2d& filter_velocity) {
  if (size_ > 0) ring_[(head_ + size_ - 1) % kCapacity].filter = filter_velocity;
}

}  // namespace labo
