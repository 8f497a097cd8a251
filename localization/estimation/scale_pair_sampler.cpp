#include "localization/estimation/scale_pair_sampler.hpp"

#include <algorithm>

namespace labo::estimation {

namespace {
constexpr Seconds kMaxFrameGap = 0.2;  // frames further apart do not form one window
}

ScalePairSampler::WindowMean ScalePairSampler::mean() const {
  WindowMean m;
  m.floor_steps_first = window_[0].floor_steps;
  m.floor_steps_last = window_[kWindow - 1].floor_steps;
  for (const ScaleSample& s : window_) {
    m.t += s.t / kWindow;
    m.p_map += s.p_map / kWindow;
    m.metric += s.metric / kWindow;
    m.max_gap = std::max(m.max_gap, s.navdata_gap);
  }
  return m;
}

void ScalePairSampler::restart(const WindowMean& now) {
  start_ = now;
  gap_since_start_ = 0;
  count_ = 0;  // the next window starts fresh: its frames are not shared with this end
}

std::optional<ScalePair> ScalePairSampler::add(const ScaleSample& sample) {
  if (count_ > 0 && sample.t - window_[count_ - 1].t > kMaxFrameGap) count_ = 0;
  if (count_ == kWindow) {
    std::rotate(window_.begin(), window_.begin() + 1, window_.end());
    --count_;
  }
  window_[count_++] = sample;
  gap_since_start_ = std::max(gap_since_start_, sample.navdata_gap);
  if (count_ < kWindow) return std::nullopt;
  const WindowMean now = mean();
  if (!start_) {
    restart(now);
    return std::nullopt;
  }
  const Seconds interval = now.t - start_->t;
  if (interval < min_) return std::nullopt;
  ScalePair pair;
  pair.map_displacement = now.p_map - start_->p_map;
  pair.metric_displacement = now.metric - start_->metric;
  pair.z_corrupted = now.floor_steps_last != start_->floor_steps_first;
  pair.coverage_ok = gap_since_start_ <= max_navdata_gap_;
  pair.interval = interval;
  Eigen::Vector3d w = weights_;
  if (pair.z_corrupted) w.z() = 0.0;
  if (w.cwiseProduct(pair.metric_displacement).norm() < min_displacement_) {
    // Not enough motion yet: the window slides on, the start waits (up to max_).
    if (interval > max_) restart(now);
    return std::nullopt;
  }
  if (interval > max_) {
    restart(now);
    return std::nullopt;
  }
  restart(now);  // consecutive pairs share their ends
  count_ = kWindow;  // ... and the window keeps sliding
  return pair;
}

}  // namespace labo::estimation
