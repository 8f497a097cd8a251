#include <catch2/catch.hpp>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "bench/experiments/experiment_common.hpp"
#include "bench/experiments/seed_runner.hpp"
#include "core/source_tree.hpp"

using namespace labo;
using namespace labo::bench;

TEST_CASE("seed runner: results come back in run order whatever finishes first") {
  for (const int jobs : {1, 2, 5}) {
    const std::vector<int> r = run_seeded_flights<int>(6, jobs, [](int i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5 * (6 - i)));  // later runs finish first
      return 10 * i;
    });
    REQUIRE(r.size() == 6);
    for (int i = 0; i < 6; ++i) CHECK(r[static_cast<std::size_t>(i)] == 10 * i);
  }
}

TEST_CASE("seed runner: a failing run's exception reaches the caller") {
  for (const int jobs : {1, 3}) {
    CHECK_THROWS_WITH(run_seeded_flights<int>(5, jobs,
                                              [](int i) {
                                                if (i == 2) throw std::runtime_error("run 2 failed");
                                                return i;
                                              }),
                      "run 2 failed");
  }
}

// A real-vision lockstep flight (rendered cameras, SLAM, planar) gives the same samples bit for bit
// when two fly at once on two threads as when each flies alone: nothing is shared between flights.
TEST_CASE("seed runner: real-vision flights in parallel equal the same seeds flown one after the other") {
  ExperimentOptions o;
  o.config = labo::source_root() / "config" / "default.json";
  o.real_vision = true;
  o.video_fps = 15;  // short: take-off, SLAM initialisation and the start of the scale manoeuvre
  const Experiment e = make_experiment(o, false);
  control::MissionRequest inspect;
  inspect.kind = control::RequestKind::Inspect;
  inspect.instrument_id = e.setup.lab.instruments.front().id;
  const auto fly = [&](int i) {
    const auto f = make_flight(e, 7 + static_cast<unsigned>(i));
    REQUIRE(f->request(inspect).accepted);
    f->run(6.0);
    return f->samples();
  };
  const std::vector<std::vector<FlightSample>> alone = run_seeded_flights<std::vector<FlightSample>>(2, 1, fly);
  const std::vector<std::vector<FlightSample>> together = run_seeded_flights<std::vector<FlightSample>>(2, 2, fly);
  for (std::size_t run = 0; run < 2; ++run) {
    REQUIRE(alone[run].size() == together[run].size());
    for (std::size_t k = 0; k < alone[run].size(); ++k) {
      INFO("run " << run << ", sample " << k);
      REQUIRE(alone[run][k].truth == together[run][k].truth);
      REQUIRE(alone[run][k].estimated == together[run][k].estimated);
      REQUIRE(alone[run][k].slam == together[run][k].slam);
    }
  }
  // The two seeds flew differently (the comparison above is not between identical flights).
  CHECK(alone[0].back().truth != alone[1].back().truth);
}
