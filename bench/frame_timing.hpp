#pragma once
// Per-frame timing for the benchmarks' figures (never fed to an algorithm): wall time and this
// thread's CPU time of one call, collected over frames and summarized. On a shared machine the wall
// time also measures the neighbours' load; the CPU time is what one core spends on the call.
#include <functional>
#include <vector>

namespace labo::bench {

// This thread's CPU time, ms.
double thread_cpu_ms();

struct CallTime {
  double wall_ms = 0, cpu_ms = 0;
};
CallTime time_call(const std::function<void()>& call);

// The q-quantile (0..1, nearest rank) of `values`; 0 for none.
double quantile_of(std::vector<double> values, double q);

struct FrameTimes {
  std::vector<double> wall_ms, cpu_ms;
  void add(const CallTime& t) {
    wall_ms.push_back(t.wall_ms);
    cpu_ms.push_back(t.cpu_ms);
  }
  std::size_t size() const { return wall_ms.size(); }
};

}  // namespace labo::bench
