#include "drone/sim/disturbances.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace labo::sim {

std::string to_string(Disturbance::Kind kind) {
  switch (kind) {
    case Disturbance::Kind::Impulse: return "impulse";
    case Disturbance::Kind::Gust: return "gust";
    case Disturbance::Kind::VideoDropout: return "video_dropout";
    case Disturbance::Kind::LinkOutage: return "link_outage";
    case Disturbance::Kind::Lighting: return "lighting";
    case Disturbance::Kind::Flicker: return "flicker";
  }
  return "?";
}

void DisturbanceSchedule::add(const Disturbance& d) {
  const auto at = std::upper_bound(items_.begin(), items_.end(), d.t_s,
                                   [](Seconds t, const Disturbance& other) { return t < other.t_s; });
  items_.insert(at, d);
}

namespace {

// 0 outside [t_s, t_s + duration_s], rising to 1 in the middle and back as a raised cosine.
double raised_cosine(const Disturbance& d, Seconds t) {
  if (t < d.t_s || t > d.t_s + d.duration_s || d.duration_s <= 0) return 0.0;
  const double phase = (t - d.t_s) / d.duration_s;
  return 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * phase));
}

}  // namespace

Eigen::Vector3d DisturbanceSchedule::wind_at(Seconds t) const {
  Eigen::Vector3d wind = Eigen::Vector3d::Zero();
  for (const auto& d : items_) {
    if (d.kind == Disturbance::Kind::Gust) wind += d.wind_world_mps * raised_cosine(d, t);
  }
  return wind;
}

double DisturbanceSchedule::exposure_gain_at(Seconds t) const {
  double gain = 1.0;
  for (const auto& d : items_) {
    if (d.kind == Disturbance::Kind::Lighting) gain *= 1.0 + (d.exposure_gain - 1.0) * raised_cosine(d, t);
    if (d.kind == Disturbance::Kind::Flicker && t >= d.t_s && t < d.t_s + d.duration_s)
      gain *= 1.0 + d.flicker_amplitude * std::sin(2.0 * std::numbers::pi * d.flicker_hz * (t - d.t_s));
  }
  return gain;
}

bool DisturbanceSchedule::active(Disturbance::Kind kind, Seconds t) const {
  return std::any_of(items_.begin(), items_.end(), [kind, t](const Disturbance& d) {
    return d.kind == kind && t >= d.t_s && t < d.t_s + d.duration_s;
  });
}

}  // namespace labo::sim
