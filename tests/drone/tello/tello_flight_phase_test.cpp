// The flight phase a Tello link reports in control_state: from its commands, the drone's replies and
// whether the motors' time still grows (a landing the link did not ask for, a flight under way).
#include <catch2/catch.hpp>

#include "drone/tello/tello_flight_phase.hpp"

using namespace labo;
using namespace labo::tello;

namespace {

TelloState motors(double seconds) {
  TelloState s;
  s.time_s = seconds;
  return s;
}

CommandOutcome outcome(const char* command, CommandOutcome::Result result) {
  CommandOutcome o;
  o.command = command;
  o.result = result;
  return o;
}

// States at 10 Hz from t0 to t1, the motors' time growing by one each second when `running`.
void feed(TelloFlightPhase& phase, double t0, double t1, double& motors_s, bool running) {
  for (double t = t0; t < t1; t += 0.1) {
    if (running) motors_s += 0.1;
    phase.on_state(motors(std::floor(motors_s)), t);
  }
}

}  // namespace

TEST_CASE("tello: take-off, flight and landing as the link commands them", "[tello][phase]") {
  TelloFlightPhase phase;
  double motors_s = 0;
  feed(phase, 0.0, 1.0, motors_s, false);
  CHECK(phase.control_state() == control_state::kLanded);
  phase.on_sent("takeoff", 1.0);
  CHECK(phase.control_state() == control_state::kTakingOff);
  feed(phase, 1.0, 5.0, motors_s, true);
  CHECK(phase.control_state() == control_state::kTakingOff);  // until the drone says it is done
  phase.on_outcome(outcome("takeoff", CommandOutcome::Result::Ok), 5.0);
  CHECK(phase.control_state() == control_state::kHovering);
  phase.on_sticks(false);
  CHECK(phase.control_state() == control_state::kFlying);
  phase.on_sticks(true);
  feed(phase, 5.0, 9.0, motors_s, true);
  CHECK(phase.control_state() == control_state::kHovering);
  phase.on_sent("land", 9.0);
  CHECK(phase.control_state() == control_state::kLanding);
  feed(phase, 9.0, 11.0, motors_s, true);
  phase.on_outcome(outcome("land", CommandOutcome::Result::Ok), 11.0);
  CHECK(phase.control_state() == control_state::kLanded);
  feed(phase, 11.0, 14.0, motors_s, false);
  CHECK(phase.control_state() == control_state::kLanded);
  CHECK(phase.unexpected_landings() == 0);
}

TEST_CASE("tello: a landing nobody commanded is seen when the motors' time stops", "[tello][phase]") {
  // The drone's 15 s watchdog or a low battery lands it: no reply ever says so.
  TelloFlightPhase phase;
  double motors_s = 0;
  phase.on_sent("takeoff", 0.0);
  feed(phase, 0.0, 4.0, motors_s, true);
  phase.on_outcome(outcome("takeoff", CommandOutcome::Result::Ok), 4.0);
  feed(phase, 4.0, 10.0, motors_s, true);
  CHECK(phase.airborne());
  feed(phase, 10.0, 12.0, motors_s, false);
  CHECK(phase.airborne());  // within 2.5 s the time may just not have ticked yet
  feed(phase, 12.0, 14.0, motors_s, false);
  CHECK(phase.control_state() == control_state::kLanded);
  CHECK(phase.unexpected_landings() == 1);

  // A silence of the link is not a stop of the motors.
  TelloFlightPhase quiet;
  motors_s = 0;
  quiet.on_sent("takeoff", 0.0);
  feed(quiet, 0.0, 4.0, motors_s, true);
  quiet.on_outcome(outcome("takeoff", CommandOutcome::Result::Ok), 4.0);
  feed(quiet, 10.0, 11.0, motors_s, true);  // 6 s without states, then states again
  CHECK(quiet.airborne());
}

TEST_CASE("tello: a flight under way when the link connects, a failed take-off, an emergency", "[tello][phase]") {
  TelloFlightPhase phase;
  double motors_s = 100;
  feed(phase, 0.0, 0.5, motors_s, true);
  CHECK(phase.control_state() == control_state::kLanded);  // one tick could be the last of a landing
  feed(phase, 0.5, 3.0, motors_s, true);
  CHECK(phase.control_state() == control_state::kHovering);

  TelloFlightPhase refused;
  refused.on_sent("takeoff", 0.0);
  refused.on_outcome(outcome("takeoff", CommandOutcome::Result::Error), 0.1);  // e.g. a low battery
  CHECK(refused.control_state() == control_state::kLanded);

  TelloFlightPhase cut;
  motors_s = 0;
  cut.on_sent("takeoff", 0.0);
  feed(cut, 0.0, 2.0, motors_s, true);
  cut.on_sent("emergency", 2.0);
  CHECK(cut.control_state() == control_state::kLanded);
  cut.on_outcome(outcome("takeoff", CommandOutcome::Result::Abandoned), 2.0);
  CHECK(cut.control_state() == control_state::kLanded);
}
