#pragma once
// SeededDraw: the random draws of one part of a run's world (the drone, the placements, the
// teacher's walk, ...), each part on its own stream: the run's seed and a tag naming the part, so a
// part drawing more or less leaves the others' draws as they were.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace labo::sim {

class SeededDraw {
 public:
  SeededDraw(std::uint64_t seed, std::uint32_t stream_tag) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), stream_tag};
    rng_.seed(seq);
  }
  double in(double min, double max) { return min + (max - min) * unit_(rng_); }
  // Within an interval that has `min` and `max`.
  template <class Interval>
  double in(const Interval& i) {
    return in(i.min, i.max);
  }
  double around(double value, double fraction) { return value * in(1.0 - fraction, 1.0 + fraction); }
  double plus_minus(double half) { return in(-half, half); }
  // Uniform in the ball of `radius` (3D, or 2D in x, y when `planar`).
  Eigen::Vector3d in_ball(double radius, bool planar = false) {
    for (;;) {
      const Eigen::Vector3d v(plus_minus(1.0), plus_minus(1.0), planar ? 0.0 : plus_minus(1.0));
      if (v.squaredNorm() <= 1.0) return radius * v;
    }
  }
  // The start times of a Poisson process of mean interval `mean_s` over [0, horizon_s).
  std::vector<double> event_times(double mean_s, double horizon_s) {
    std::vector<double> times;
    for (double t = -mean_s * std::log(1.0 - unit_(rng_)); t < horizon_s; t += -mean_s * std::log(1.0 - unit_(rng_)))
      times.push_back(t);
    return times;
  }

 private:
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
};

}  // namespace labo::sim
