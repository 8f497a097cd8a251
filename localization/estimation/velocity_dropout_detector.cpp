#include "localization/estimation/velocity_dropout_detector.hpp"

#include <algorithm>
#include <cmath>

namespace labo::estimation {

namespace {
Eigen::Vector2d rotate(double yaw, const Eigen::Vector2d& v) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}
}  // namespace

void VelocityDropoutDetector::reset() {
  restart();
  bias_heading_.setZero();
  bias_time_ = 0;
}

void VelocityDropoutDetector::restart() {
  head_ = size_ = 0;
  in_dropout_ = false;
  dropout_start_ = 0;
  onset_votes_ = resume_votes_ = 0;
  shadow_.setZero();
  consistent_since_ = shadow_reset_t_ = 0;
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

void VelocityDropoutDetector::push(const Entry& e) {
  if (size_ == kCapacity) {
    head_ = (head_ + 1) % kCapacity;
    --size_;
  }
  ring_[(head_ + size_) % kCapacity] = e;
  ++size_;
}

VelocityDropoutDetector::Window VelocityDropoutDetector::window() const {
  Window w;
  if (size_ < 2) return w;
  const Seconds now = at(size_ - 1).t;
  if (at(0).t > now - 0.5 * settings_.window_s) return w;
  w.start = first_at_or_after(now - settings_.window_s);
  if (w.start + 1 >= size_) return w;
  w.start_end = std::max(w.start, first_at_or_after(at(w.start).t + settings_.average_s) - 1);
  w.end_begin = std::max(w.start + 1, first_at_or_after(now - settings_.average_s));
  w.valid = w.start_end < w.end_begin;
  return w;
}

Eigen::Vector2d VelocityDropoutDetector::model_from_measured(const Window& w) const {
  Eigen::Vector2d v = mean_measured(w.start, w.start_end);
  Eigen::Vector2d end_sum = Eigen::Vector2d::Zero();
  for (std::size_t i = w.start + 1; i < size_; ++i) {
    v += (at(i - 1).thrust_accel - model_.drag_per_s * v) * (at(i).t - at(i - 1).t);
    if (i >= w.end_begin) end_sum += v;
  }
  return end_sum / static_cast<double>(size_ - w.end_begin);
}

void VelocityDropoutDetector::learn_bias(const Window& w, double yaw, Seconds dt) {
  // Over the window, the model from the measured start against the measured end: what is left is the
  // bias times the window's effective length (the drag forgets part of it).
  const Eigen::Vector2d residual = mean_measured(w.end_begin, size_ - 1) - model_from_measured(w);
  const Seconds span = 0.5 * (at(size_ - 1).t + at(w.end_begin).t) - 0.5 * (at(w.start).t + at(w.start_end).t);
  if (!(span > 0)) return;
  const double effective = (1.0 - std::exp(-model_.drag_per_s * span)) / model_.drag_per_s;
  const Eigen::Vector2d error_world = -residual / effective;  // what the model still overstates
  // A larger residual is a manoeuvre the model misses, or a flow starting to fail: not an offset.
  if (error_world.norm() > kBiasGateMps2) return;
  bias_time_ = std::min(bias_time_ + dt, kBiasWarmup);
  // A running mean over the warm-up, then a slow exponential average.
  const double gain = bias_time_ < kBiasWarmup ? dt / bias_time_ : dt / kBiasTimeConstant;
  bias_heading_ += std::min(1.0, gain) * rotate(-yaw, error_world);
}

double VelocityDropoutDetector::unexplained_by_failing_flow(const Eigen::Vector2d& measured) const {
  // A failing flow shrinks the true velocity towards zero along its direction: what it can explain of
  // `measured` is its part along the shadow's velocity, between zero and the shadow's speed.
  const double speed = shadow_.norm();
  const Eigen::Vector2d along_unit = speed > 1e-9 ? Eigen::Vector2d(shadow_ / speed) : Eigen::Vector2d::Zero();
  const double along = measured.dot(along_unit);
  const double beyond = along > speed ? along - speed : along < 0 ? -along : 0.0;
  return std::hypot(beyond, (measured - along * along_unit).norm());
}

void VelocityDropoutDetector::take_back() {
  // Since the model and the flow last agreed (at least the last window), at most kTakeBackMaxS:
  // a flow fails at once, and further back the shadow's own drift is what would be taken back (the
  // ring alone reaches 17 s at 15 Hz, 25 s at the Tello's 10 Hz; once 0.87 m was taken back).
  correction_ = {};
  const Seconds now = at(size_ - 1).t;
  const Seconds since =
      std::max({shadow_reset_t_, now - std::max(kTakeBackMaxS, settings_.window_s), std::min(consistent_since_, now - settings_.window_s)});
  const std::size_t start = first_at_or_after(since);
  for (std::size_t i = std::max<std::size_t>(start, 1); i < size_; ++i) {
    const double dt = at(i).t - at(i - 1).t;
    correction_.position += 0.5 * ((at(i).shadow - at(i).filter) + (at(i - 1).shadow - at(i - 1).filter)) * dt;
  }
  correction_.velocity = at(size_ - 1).shadow - at(size_ - 1).filter;
}

VelocityVerdict VelocityDropoutDetector::process(Seconds t, const Eigen::Vector2d& measured_world,
                                                 const Eigen::Vector2d& thrust_accel_world, double yaw,
                                                 const Eigen::Vector2d& filter_velocity) {
  if (size_ > 0 && t < at(size_ - 1).t) restart();  // time went back: a new flight
  // After a gap in the navdata (a Wi-Fi cut) longer than the firmware's command hold the model knows
  // nothing of what the drone did meanwhile: the firmware hovered it to a stop, and a shadow carried
  // across still flying read the stopped drone's zero as a failed flow, whose take-back threw the
  // estimate metres on.
  if (size_ > 0 && t - at(size_ - 1).t > firmware_command_hold_s_) restart();
  const Eigen::Vector2d thrust = thrust_accel_world - rotate(yaw, bias_heading_);
  if (size_ == 0) {
    shadow_ = measured_world;
  } else {
    const Seconds dt = t - at(size_ - 1).t;
    const Eigen::Vector2d pull =
        in_dropout_ ? Eigen::Vector2d::Zero() : Eigen::Vector2d(kShadowPullPerS * (measured_world - shadow_));
    shadow_ += (at(size_ - 1).thrust_accel - model_.drag_per_s * shadow_ + pull) * dt;
  }
  const Seconds dt = size_ > 0 ? t - at(size_ - 1).t : 0.0;
  push({t, measured_world, thrust, filter_velocity, shadow_});

  VelocityVerdict verdict;
  const Window w = window();
  if (!w.valid) {
    verdict.fuse = !in_dropout_;
    return verdict;
  }
  const Eigen::Vector2d measured_now = mean_measured(w.end_begin, size_ - 1);
  if (!in_dropout_) {
    if (unexplained_by_failing_flow(measured_now) > settings_.onset_mps) {
      // The drone moved in a way the model cannot know (a push, a gust, a collision): the flow is
      // right, the model's velocity takes it.
      shadow_ = measured_now;
      back().shadow = shadow_;
      shadow_reset_t_ = consistent_since_ = t;
      onset_votes_ = 0;
      return verdict;
    }
    const double measured_speed = measured_now.norm(), model_speed = shadow_.norm();
    const bool lost = warmed_up() && model_speed - measured_speed > settings_.onset_mps &&
                      measured_speed < settings_.onset_ratio * model_speed;
    onset_votes_ = lost ? onset_votes_ + 1 : 0;
    if (onset_votes_ >= settings_.confirm_packets) {
      take_back();
      in_dropout_ = true;
      dropout_start_ = t;
      onset_votes_ = resume_votes_ = 0;
      verdict.onset = true;
      verdict.fuse = false;
      return verdict;
    }
    // After the warm-up, learned only while the flow shows motion and agrees with the model: reading
    // zero, a failed flow and a hover look alike, and a drone creeping on a small tilt while the flow
    // reads zero would be learned as an offset.
    const bool consistent = model_speed - measured_speed < 0.5 * settings_.onset_mps;
    if (consistent) consistent_since_ = t;
    if (!warmed_up() || (consistent && measured_speed > settings_.alive_mps)) learn_bias(w, yaw, dt);
    return verdict;
  }
  const double measured_speed = measured_now.norm();
  const bool alive = measured_speed > settings_.alive_mps &&
                     measured_speed > model_from_measured(w).norm() - settings_.onset_mps;
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
  if (size_ > 0) back().filter = filter_velocity;
}

}  // namespace labo::estimation
