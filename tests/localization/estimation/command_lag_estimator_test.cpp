#include <catch2/catch.hpp>
#include <cmath>
#include <deque>
#include <limits>
#include <random>

#include "localization/estimation/command_lag_estimator.hpp"

using namespace labo;
using namespace labo::estimation;

namespace {

// A first-order attitude plant: commands act control_delay after they are sent, navdata is received
// navdata_delay after it is measured; a tilt offset and sensor noise as the lab's IMU has.
struct LaggedAttitudePlant {
  double rate_hz = 7.0;          // the lab firmware's attitude rate (the estimator is given 6.5)
  double tilt_max_rad = 0.21;
  Seconds control_delay = 0.100;
  Seconds navdata_delay = 0.040;
  double offset_rad = 0.01;
  double noise_rad = 0.002;
  int control_state = 3;         // flying
  bool excite = true;
};

// Flies `duration` seconds: random command steps every 0.3-1.0 s sent at 30 Hz, navdata at `rate_hz`.
void fly(const LaggedAttitudePlant& p, estimation::CommandLagEstimator& estimator, Seconds duration, double navdata_hz,
         unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(-0.6, 0.6), hold(0.3, 1.0);
  std::normal_distribution<double> noise(0.0, p.noise_rad);
  constexpr Seconds dt = 0.001;
  std::deque<std::pair<Seconds, MoveCommand>> in_flight;  // sent, not yet acting
  MoveCommand sent, acting;
  double roll = 0, pitch = 0;
  std::deque<std::pair<Seconds, NavdataSample>> on_the_way;  // measured, not yet received
  Seconds next_step = 0, next_send = 0, next_measure = 0;
  for (Seconds t = 0; t < duration; t += dt) {
    if (p.excite && t >= next_step) {
      sent.roll = level(rng);
      sent.pitch = level(rng);
      next_step = t + hold(rng);
    }
    if (t >= next_send) {
      estimator.add_command(sent, t);
      in_flight.emplace_back(t + p.control_delay, sent);
      next_send = t + 1.0 / 30.0;
    }
    while (!in_flight.empty() && in_flight.front().first <= t) {
      acting = in_flight.front().second;
      in_flight.pop_front();
    }
    const double k = 1.0 - std::exp(-p.rate_hz * dt);
    roll += k * (acting.roll * p.tilt_max_rad - roll);
    pitch += k * (acting.pitch * p.tilt_max_rad - pitch);
    if (t >= next_measure) {
      NavdataSample s;
      s.t = t + p.navdata_delay;
      s.control_state = p.control_state;
      s.roll_rad = roll + p.offset_rad + noise(rng);
      s.pitch_rad = pitch - p.offset_rad + noise(rng);
      on_the_way.emplace_back(s.t, s);
      next_measure = t + 1.0 / navdata_hz;
    }
    while (!on_the_way.empty() && on_the_way.front().first <= t) {
      estimator.add_navdata(on_the_way.front().second);
      on_the_way.pop_front();
    }
  }
}

estimation::MotionModelConstants fitted_model() {
  estimation::MotionModelConstants m;
  m.attitude_rate_hz = 6.5;  // the lab fit's figure, not the plant's 7.0
  m.tilt_max_rad = 0.21;
  return m;
}

}  // namespace

TEST_CASE("estimation: the command round trip is measured from flight data (200 Hz and 15 Hz navdata)") {
  const double navdata_hz = GENERATE(200.0, 15.0);
  CAPTURE(navdata_hz);
  LaggedAttitudePlant plant;
  estimation::CommandLagEstimator estimator(fitted_model());
  fly(plant, estimator, 40.0, navdata_hz, 7);
  const auto lag = estimator.estimate();
  REQUIRE(lag.has_value());
  CHECK(lag->windows >= 5);
  // The model's slower attitude lag (6.5 /s against the plant's 7.0) is absorbed as ~6 ms less delay.
  CHECK(lag->round_trip_s == Approx(0.140).margin(0.015));
  CHECK(estimator.counters().windows_accepted >= 5);
}

TEST_CASE("estimation: a different round trip is found, not a fixed figure") {
  LaggedAttitudePlant plant;
  plant.control_delay = 0.020;
  plant.navdata_delay = 0.030;
  estimation::CommandLagEstimator estimator(fitted_model());
  fly(plant, estimator, 40.0, 200.0, 11);
  const auto lag = estimator.estimate();
  REQUIRE(lag.has_value());
  CHECK(lag->round_trip_s == Approx(0.050).margin(0.015));

  LaggedAttitudePlant slow = plant;
  slow.control_delay = 0.250;
  estimation::CommandLagEstimator estimator_slow(fitted_model());
  fly(slow, estimator_slow, 40.0, 200.0, 11);
  REQUIRE(estimator_slow.estimate().has_value());
  CHECK(estimator_slow.estimate()->round_trip_s == Approx(0.280).margin(0.015));
}

TEST_CASE("estimation: no round trip without commands that move, nor from a landed drone") {
  SECTION("hover: the commands never change") {
    LaggedAttitudePlant plant;
    plant.excite = false;
    estimation::CommandLagEstimator estimator(fitted_model());
    fly(plant, estimator, 30.0, 200.0, 3);
    CHECK_FALSE(estimator.estimate().has_value());
    CHECK(estimator.counters().windows_low_excitation > 0);
  }
  SECTION("landed: the firmware ignores PCMD") {
    LaggedAttitudePlant plant;
    plant.control_state = 2;
    estimation::CommandLagEstimator estimator(fitted_model());
    fly(plant, estimator, 30.0, 200.0, 3);
    CHECK_FALSE(estimator.estimate().has_value());
    CHECK(estimator.counters().windows_accepted == 0);
  }
}

TEST_CASE("estimation: the command lag estimator refuses non-finite and out-of-order inputs") {
  estimation::CommandLagEstimator estimator(fitted_model());
  NavdataSample s;
  s.t = 1.0;
  s.control_state = 3;
  estimator.add_navdata(s);
  s.t = 0.5;
  estimator.add_navdata(s);
  s.t = 2.0;
  s.pitch_rad = std::nan("");
  estimator.add_navdata(s);
  MoveCommand c;
  estimator.add_command(c, 1.0);
  estimator.add_command(c, 0.9);
  c.roll = std::numeric_limits<double>::infinity();
  estimator.add_command(c, 1.1);
  CHECK(estimator.counters().navdata == 1);
  CHECK(estimator.counters().commands == 1);
  CHECK(estimator.counters().rejected_out_of_order == 2);
  CHECK(estimator.counters().rejected_nonfinite == 2);

  estimation::MotionModelConstants bad = fitted_model();
  bad.attitude_rate_hz = 0;
  CHECK_THROWS_WITH(CommandLagEstimator(bad), Catch::Contains("attitude_rate_hz"));
  estimation::CommandLagSettings settings;
  settings.horizon_s = settings.window_s;
  CHECK_THROWS_WITH(CommandLagEstimator(fitted_model(), settings), Catch::Contains("horizon_s < window_s"));
}
