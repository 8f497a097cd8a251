#include "drone/ardrone2/link_counters.hpp"

namespace labo::ardrone2 {

void LinkCounters::add(std::string_view kind, std::uint64_t n) {
  std::lock_guard lock(mutex_);
  auto it = counters_.find(kind);
  if (it == counters_.end()) it = counters_.emplace(std::string(kind), 0).first;  // allocates once per kind
  it->second += n;
}

void LinkCounters::bad_input(std::string_view kind, Seconds t, std::string_view detail) {
  add(kind);
  std::size_t suppressed = 0;
  if (limiter_.allow(kind, t, &suppressed)) {
    logger_.warn(t, "bad input dropped").kv("kind", kind).kv("detail", detail).kv("suppressed", suppressed);
  }
}

std::uint64_t LinkCounters::get(std::string_view kind) const {
  std::lock_guard lock(mutex_);
  const auto it = counters_.find(kind);
  return it == counters_.end() ? 0 : it->second;
}

LinkStatistics LinkCounters::snapshot() const {
  std::lock_guard lock(mutex_);
  LinkStatistics s;
  s.counters.insert(counters_.begin(), counters_.end());
  s.navdata_rate_hz = navdata_hz_;
  s.video_fps = video_fps_;
  return s;
}

void LinkCounters::set_rates(double navdata_hz, double video_fps) {
  std::lock_guard lock(mutex_);
  navdata_hz_ = navdata_hz;
  video_fps_ = video_fps;
}

}  // namespace labo::ardrone2
