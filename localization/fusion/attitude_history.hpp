#pragma once
// The IMU's roll and pitch over the last navdata packets, at their measurement times, so that each
// video frame can be given the attitude at its own capture time (SLAM's gravity prior): navdata and
// video arrive with different delays (40 and 75 ms in the simulated link), so "the latest navdata"
// is not the frame's attitude during a manoeuvre. A fixed ring: no allocation per packet.
#include <array>
#include <cstddef>
#include <optional>

#include "core/time.hpp"

namespace labo::fusion {

struct Attitude {
  double roll_rad = 0, pitch_rad = 0;
};

class AttitudeHistory {
 public:
  // A sample measured at t_meas. A time before the newest (a new run) starts the history again.
  void add(Seconds t_meas, const Attitude& attitude);
  // Linear interpolation between the samples around t; the newest sample held up to `max_hold_s`
  // past it (navdata at 15 Hz may not have caught up with the frame yet). Empty otherwise, and when
  // the samples around t are more than `max_gap_s` apart.
  std::optional<Attitude> at(Seconds t, Seconds max_hold_s = 0.1, Seconds max_gap_s = 0.25) const;
  void clear() { size_ = 0; }

 private:
  struct Sample {
    Seconds t = 0;
    Attitude attitude;
  };
  const Sample& newest(std::size_t back) const { return ring_[(next_ + kSize - 1 - back) % kSize]; }
  static constexpr std::size_t kSize = 64;  // 0.3 s at 200 Hz, 4 s at 15 Hz
  std::array<Sample, kSize> ring_{};
  std::size_t next_ = 0, size_ = 0;
};

}  // namespace labo::fusion
