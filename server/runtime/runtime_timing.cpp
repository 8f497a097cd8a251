#include "server/runtime/runtime_timing.hpp"

#include <algorithm>

namespace labo::server {

RuntimeTiming::RuntimeTiming(std::size_t window) {
  for (Ring* r : {&ticks_, &latency_, &latency_tracking_, &run_}) r->values.assign(std::max<std::size_t>(window, 1), 0.0);
}

void RuntimeTiming::Ring::add(double v) {
  values[next] = v;
  next = (next + 1) % values.size();
  if (next == 0) full = true;
}

Percentiles RuntimeTiming::Ring::percentiles() const {
  std::vector<double> v(values.begin(), full ? values.end() : values.begin() + static_cast<std::ptrdiff_t>(next));
  Percentiles p;
  p.count = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)]; };
  p.median = at(0.5);
  p.p95 = at(0.95);
  p.p99 = at(0.99);
  p.max = v.back();
  return p;
}

void RuntimeTiming::add_tick_interval(double ms) {
  std::lock_guard lock(mutex_);
  ticks_.add(ms);
}

void RuntimeTiming::add_vision(double latency_ms, double run_ms, bool tracking) {
  std::lock_guard lock(mutex_);
  latency_.add(latency_ms);
  if (tracking) latency_tracking_.add(latency_ms);
  run_.add(run_ms);
}

void RuntimeTiming::count_frame_in() {
  std::lock_guard lock(mutex_);
  ++counts_.frames_in;
}

void RuntimeTiming::count_frame_to_vision() {
  std::lock_guard lock(mutex_);
  ++counts_.frames_to_vision;
}

void RuntimeTiming::count_frame_skipped() {
  std::lock_guard lock(mutex_);
  ++counts_.frames_skipped;
}

void RuntimeTiming::count_vision_failure() {
  std::lock_guard lock(mutex_);
  ++counts_.vision_failures;
}

RuntimeTimingSummary RuntimeTiming::summary() const {
  std::lock_guard lock(mutex_);
  RuntimeTimingSummary s = counts_;
  s.tick_interval_ms = ticks_.percentiles();
  s.vision_latency_ms = latency_.percentiles();
  s.vision_latency_tracking_ms = latency_tracking_.percentiles();
  s.vision_run_ms = run_.percentiles();
  return s;
}

}  // namespace labo::server
