#pragma once
// The process's CPU time, for the simulated lab's stage profile and `labodrone-bench bench sim`: on a
// machine shared with other jobs, wall time measures the neighbours; CPU time measures our work.
#include <ctime>

namespace labo {

inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace labo
