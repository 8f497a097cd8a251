#pragma once
// ScalePairSampler: cuts the SLAM track and the metric navdata odometry into the displacement pairs the
// ScaleEstimator needs (notes/tum_ardrone.md §3). Each end of a pair is the mean of a short window of
// consecutive fused SLAM frames (and of the odometry at the same instants), which divides the
// per-frame SLAM noise by about sqrt(window) without biasing the ratio: both sides are averaged over the
// same frames. Intervals shorter than `min_interval` wait, longer than `max_interval` restart.
#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/time.hpp"

namespace labo {

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

  ScalePairSampler(Seconds min_interval, Seconds max_interval) : min_(min_interval), max_(max_interval) {}
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

  Seconds min_;
  Seconds max_;
  std::array<ScaleSample, kWindow> window_{};
  int count_ = 0;  // samples in the window (consecutive)
  std::optional<WindowMean> start_;
  Seconds gap_since_start_ = 0;
};

}  // namespace labo
