#include "localization/fusion/attitude_history.hpp"

#include <cmath>

namespace labo::fusion {

void AttitudeHistory::add(Seconds t_meas, const Attitude& attitude) {
  if (!std::isfinite(t_meas) || !std::isfinite(attitude.roll_rad) || !std::isfinite(attitude.pitch_rad)) return;
  if (size_ > 0 && t_meas <= newest(0).t) {
    if (t_meas == newest(0).t) return;  // a repeated packet
    clear();
  }
  ring_[next_] = {t_meas, attitude};
  next_ = (next_ + 1) % kSize;
  if (size_ < kSize) ++size_;
}

std::optional<Attitude> AttitudeHistory::at(Seconds t, Seconds max_hold_s, Seconds max_gap_s) const {
  if (size_ == 0 || !std::isfinite(t)) return std::nullopt;
  const Sample& last = newest(0);
  if (t >= last.t) {
    if (t - last.t > max_hold_s) return std::nullopt;
    return last.attitude;
  }
  for (std::size_t back = 1; back < size_; ++back) {
    const Sample& before = newest(back);
    if (before.t > t) continue;
    const Sample& after = newest(back - 1);
    if (after.t - before.t > max_gap_s) return std::nullopt;
    const double w = (t - before.t) / (after.t - before.t);
    return Attitude{before.attitude.roll_rad + w * (after.attitude.roll_rad - before.attitude.roll_rad),
                    before.attitude.pitch_rad + w * (after.attitude.pitch_rad - before.attitude.pitch_rad)};
  }
  return std::nullopt;  // older than the history
}

}  // namespace labo::fusion
