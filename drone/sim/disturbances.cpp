#include "drone/sim/disturbances.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace labo {

std::string to_string(Disturbance::Kind kind) {
  switch (kind) {
    case Disturbance::Kind::Impulse: return "impulse";
    case Disturbance::Kind::Gust: return "gust";
    case Disturbance::Kind::VideoDropout: return "video_dropout";
    case Disturbance::Kind::LinkOutage: return "link_outage";
  }
  return "?";
}

void DisturbanceSchedule::add(const Disturbance& d) {
  const auto at = std::upper_bound(items_.begin(), items_.end(), d.t_s,
                                   [](Seconds t, const Disturbance& other) { return t < other.t_s; });
  items_.insert(at, d);
}

Eigen::Vector3d DisturbanceSchedule::wind_at(Seconds t) const {
  Eigen::Vector3d wind = Eigen::Vector3d::Zero();
  for (const auto& d : items_) {
    if (d.kind != Disturbance::Kind::Gust || t < d.t_s || t > d.t_s + d.duration_s || d.duration_s <= 0) continue;
    const double phase = (t - d.t_s) / d.duration_s;  // 0..1: up and down again
    wind += d.wind_world_mps * 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * phase));
  }
  return wind;
}

bool DisturbanceSchedule::active(Disturbance::Kind kind, Seconds t) const {
  return std::any_of(items_.begin(), items_.end(), [kind, t](const Disturbance& d) {
    return d.kind == kind && t >= d.t_s && t < d.t_s + d.duration_s;
  });
}

}  // namespace labo
