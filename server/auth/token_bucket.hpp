#pragma once
// A token bucket: `rate_per_s` tokens refill per second up to `burst`; each action takes one. Time is
// passed in (seconds on any monotonic clock) so tests can drive it.
#include <algorithm>

namespace labo::server {

class TokenBucket {
 public:
  TokenBucket(double rate_per_s, double burst) : rate_(rate_per_s), burst_(burst), tokens_(burst) {}
  bool take(double now_s) {
    if (last_s_ >= 0) tokens_ = std::min(burst_, tokens_ + (now_s - last_s_) * rate_);
    last_s_ = now_s;
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }

 private:
  double rate_;
  double burst_;
  double tokens_;
  double last_s_ = -1;
};

}  // namespace labo::server
