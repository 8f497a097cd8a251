#pragma once
// Disturbances of the simulated lab, scheduled by simulated time (from the "sim" config section or
// through SimulatedLab::schedule()):
//  - impulse: a push at one instant, as in the paper's Figs 5-8 (someone knocks the hovering drone):
//    a velocity change along the drone's heading frame (x forward, y left, z up) and a yaw turn;
//  - gust: wind (world frame) over an interval, rising and falling as a raised cosine; the drone's
//    drag acts on its velocity relative to the air;
//  - video_dropout: no camera frame over an interval (the Wi-Fi video stream stalls);
//  - link_outage: nothing gets through the Wi-Fi over an interval, either way (SimDroneLink): the
//    firmware hovers after its 2 s command timeout, the driver sees the link degrade and get lost;
//  - lighting: the light changes over an interval (a lamp switched on, sun through a window, the
//    camera's auto-exposure catching up): the frames' exposure is multiplied by a factor that rises
//    to `exposure_gain` and falls back as a raised cosine. Vision must survive it (the planar
//    benchmark's lighting case, in flight);
//  - flicker: the lamps' mains flicker as the camera samples it: the exposure is multiplied by
//    1 + amplitude·sin(2π·frequency·(t − t_s)) over an interval.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace labo::sim {

struct Disturbance {
  enum class Kind { Impulse, Gust, VideoDropout, LinkOutage, Lighting, Flicker };
  Kind kind = Kind::Impulse;
  Seconds t_s = 0;
  Seconds duration_s = 0;                                   // all but the impulse
  Eigen::Vector3d dv_heading_mps = Eigen::Vector3d::Zero();  // impulse
  double dyaw_rad = 0;                                      // impulse: the turn it causes
  Eigen::Vector3d wind_world_mps = Eigen::Vector3d::Zero();  // gust: the peak wind
  double exposure_gain = 1.0;                               // lighting: the peak exposure factor
  double flicker_amplitude = 0;                             // flicker: relative exposure swing
  double flicker_hz = 0;                                    // flicker: its frequency as sampled
};

std::string to_string(Disturbance::Kind kind);

// The schedule, queried by time. Impulses are handed out once each, in time order.
class DisturbanceSchedule {
 public:
  void add(const Disturbance& d);
  // Impulses with t_s in (after, up_to], in time order.
  template <typename F>
  void for_each_impulse(Seconds after, Seconds up_to, F&& f) const {
    for (const auto& d : items_)
      if (d.kind == Disturbance::Kind::Impulse && d.t_s > after && d.t_s <= up_to) f(d);
  }
  // The sum of the gusts' winds at t.
  Eigen::Vector3d wind_at(Seconds t) const;
  // The product of the lighting changes' and flickers' exposure factors at t (1 when none is active).
  double exposure_gain_at(Seconds t) const;
  bool video_dropout_at(Seconds t) const { return active(Disturbance::Kind::VideoDropout, t); }
  bool link_outage_at(Seconds t) const { return active(Disturbance::Kind::LinkOutage, t); }
  const std::vector<Disturbance>& items() const { return items_; }
  bool empty() const { return items_.empty(); }

 private:
  bool active(Disturbance::Kind kind, Seconds t) const;
  std::vector<Disturbance> items_;  // sorted by t_s
};

}  // namespace labo::sim
