#pragma once
// Thread-safe counters by kind for LinkStatistics, plus bad-input reporting: every bad input is
// counted under its kind and logged at most once a second per kind (with how many were suppressed).
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

#include "core/log.hpp"
#include "drone/drone_link.hpp"

namespace labo::ardrone2 {

class LinkCounters {
 public:
  explicit LinkCounters(Logger logger) : logger_(std::move(logger)) {}
  void add(std::string_view kind, std::uint64_t n = 1);
  // Counts and logs (rate-limited) one bad input of `kind` at time t.
  void bad_input(std::string_view kind, Seconds t, std::string_view detail);
  std::uint64_t get(std::string_view kind) const;
  LinkStatistics snapshot() const;
  void set_rates(double navdata_hz, double video_fps);

 private:
  Logger logger_;
  RateLimiter limiter_{1.0};
  mutable std::mutex mutex_;
  std::map<std::string, std::uint64_t, std::less<>> counters_;
  double navdata_hz_ = 0, video_fps_ = 0;
};

}  // namespace labo::ardrone2
