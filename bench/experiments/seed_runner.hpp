#pragma once
// Runs an experiment's seeded flights on several threads (`--jobs N`): run i of `runs` is
// `fly(i)`, and the results come back in run order whatever finished first. Every flight owns its
// simulated lab, link, stack and front-ends, and a lockstep flight depends on nothing but its seed,
// so run i gives the same result alone, in a batch, or beside other runs on other threads
// (tests/bench/experiments/seed_runner_test.cpp; docs/control.md). The batch's wall time drops with
// free cores; its CPU time does not.
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace labo::bench {

// The first exception a flight throws is rethrown here, after every started flight has ended.
template <typename Result>
std::vector<Result> run_seeded_flights(int runs, int jobs, const std::function<Result(int)>& fly) {
  std::vector<std::optional<Result>> slots(static_cast<std::size_t>(std::max(0, runs)));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (int i = next++; i < runs; i = next++) {
      try {
        slots[static_cast<std::size_t>(i)].emplace(fly(i));
      } catch (...) {
        const std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = runs;  // start no new flight
      }
    }
  };
  const int threads = std::clamp(jobs, 1, std::max(1, runs));
  if (threads == 1) {
    worker();
  } else {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  }
  if (failure) std::rethrow_exception(failure);
  std::vector<Result> results;
  results.reserve(slots.size());
  for (auto& s : slots) results.push_back(std::move(*s));
  return results;
}

}  // namespace labo::bench
