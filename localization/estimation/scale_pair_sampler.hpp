#pragma once
// ScalePairSampler: cuts the SLAM track and the metric navdata odometry into the displacement pairs the
// ScaleEstimator needs (notes/tum_ardrone.md §3). Each end of a pair is the mean of a short window of
// consecutive fused SLAM frames (and of the odometry at the same instants), which divides the
// per-frame SLAM noise by about sqrt(window) without biasing the ratio: both sides are averaged over the
// same frames. A pair closes once its interval is at least `min_interval` and its weighted metric
// displacement reaches `min_displacement` (any motion, not only the up/down manoeuvre: a pair that
// closed after a fixed interval was mostly too short to count, and was thrown away); an interval
// longer than `max_interval` without enough motion restarts (odometry drift grows with time). A pair
// whose odometry has a navdata gap longer than `max_navdata_gap` is marked without coverage: the gap
// allowed depends on the telemetry's rate (1.5 periods: 0.1 s at the AR.Drone's 15 Hz demo navdata,
// 0.15 s at a Tello's 10 Hz state; the estimation section's scale_max_navdata_gap_s).
#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/time.hpp"

namespace labo::estimation {

struct ScaleSample {
  Seconds t = 0;
  Eigen::Vector3d p_map = Eigen::Vector3d::Zero();     // camera position in the map (map units)
  Eigen::Vector3d metric = Eigen::Vector3d::Zero();    // camera position from navdata odometry (m)
  int floor_steps = 0;                                 // floor steps seen so far (z corrupted if it changes)
  Seconds navdata_gap = 0;                             // largest navdata interval since the previous sample
};

struct ScalePair {
  Eigen::Vector3d map_displacement;     // map units
  Eigen::Vector3d metric_displacement;  // m
  bool z_corrupted = false;
  bool coverage_ok = true;              // no navdata gap above 0.1 s
  Seconds interval = 0;
};

class ScalePairSampler {
 public:
  static constexpr int kWindow = 5;

  // `weights`: per world axis (x, y, z), as the ScaleEstimator will see the pair (z counts 0 once a
  // floor step corrupted it).
  ScalePairSampler(Seconds min_interval, Seconds max_interval, const Eigen::Vector3d& weights, double min_displacement,
                   Seconds max_navdata_gap = 0.1)
      : min_(min_interval), max_(max_interval), weights_(weights), min_displacement_(min_displacement),
        max_navdata_gap_(max_navdata_gap) {}
  void reset() { count_ = 0; start_.reset(); }
  // Adds a fused SLAM frame; returns a pair when one completes.
  std::optional<ScalePair> add(const ScaleSample& sample);

 private:
  struct WindowMean {
    Seconds t = 0;
    Eigen::Vector3d p_map = Eigen::Vector3d::Zero();
    Eigen::Vector3d metric = Eigen::Vector3d::Zero();
    int floor_steps_first = 0;
    int floor_steps_last = 0;
    Seconds max_gap = 0;
  };
  WindowMean mean() const;

  void restart(const WindowMean& now);

  Seconds min_;
  Seconds max_;
  Eigen::Vector3d weights_;
  double min_displacement_;
  Seconds max_navdata_gap_;
  std::array<ScaleSample, kWindow> window_{};
  int count_ = 0;  // samples in the window (consecutive)
  std::optional<WindowMean> start_;
  Seconds gap_since_start_ = 0;
};

}  // namespace labo::estimation
