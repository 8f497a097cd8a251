#include "bench/frame_timing.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>

namespace labo::bench {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

CallTime time_call(const std::function<void()>& call) {
  const auto start = std::chrono::steady_clock::now();
  const double start_cpu = thread_cpu_ms();
  call();
  CallTime t;
  t.cpu_ms = thread_cpu_ms() - start_cpu;
  t.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return t;
}

double quantile_of(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1) + 0.5;
  return values[std::min(values.size() - 1, static_cast<std::size_t>(rank))];
}

}  // namespace labo::bench
