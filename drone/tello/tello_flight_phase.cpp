#include "drone/tello/tello_flight_phase.hpp"

namespace labo::tello {

namespace {
constexpr Seconds kStateGapS = 1.0;      // states further apart than this: the link was silent
constexpr int kGrowthsToBeAirborne = 2;  // `time` growing twice while landed: the motors really run
}  // namespace

void TelloFlightPhase::on_sent(std::string_view command, Seconds) {
  if (command == "takeoff" && phase_ == Phase::Landed) {
    phase_ = Phase::TakingOff;
  } else if (command == "land" && phase_ != Phase::Landed) {
    phase_ = Phase::Landing;
  } else if (command == "emergency") {
    phase_ = Phase::Landed;  // motors cut at once
    growths_while_landed_ = 0;
  }
}

void TelloFlightPhase::on_outcome(const CommandOutcome& o, Seconds t) {
  using Result = CommandOutcome::Result;
  if (o.result == Result::Abandoned) return;
  const bool ok = o.result == Result::Ok;
  if (o.command == "takeoff" && phase_ == Phase::TakingOff) {
    phase_ = ok || motors_running(t) ? Phase::Airborne : Phase::Landed;
  } else if (o.command == "land" && phase_ == Phase::Landing) {
    phase_ = !ok && motors_running(t) ? Phase::Airborne : Phase::Landed;
  }
  if (phase_ == Phase::Landed) growths_while_landed_ = 0;
}

void TelloFlightPhase::on_state(const TelloState& s, Seconds t) {
  if (motors_seen_t_ < 0 || t - motors_seen_t_ > kStateGapS) {
    motors_changed_t_ = t;  // after a silence nothing is known yet: give the motors' time a chance to tick
  } else if (s.time_s > motors_s_) {
    motors_changed_t_ = t;
    if (phase_ == Phase::Landed) ++growths_while_landed_;
  }
  motors_s_ = s.time_s;
  motors_seen_t_ = t;
  const bool running = motors_running(t);
  if (phase_ == Phase::Airborne && !running) {
    phase_ = Phase::Landed;  // the drone landed by itself (its watchdog, a low battery)
    ++unexpected_landings_;
    growths_while_landed_ = 0;
  } else if (phase_ == Phase::Landing && !running) {
    phase_ = Phase::Landed;
    growths_while_landed_ = 0;
  } else if (phase_ == Phase::Landed && growths_while_landed_ >= kGrowthsToBeAirborne) {
    phase_ = Phase::Airborne;  // flying already when the link connected
  }
}

int TelloFlightPhase::control_state() const {
  switch (phase_) {
    case Phase::Landed: return control_state::kLanded;
    case Phase::TakingOff: return control_state::kTakingOff;
    case Phase::Landing: return control_state::kLanding;
    case Phase::Airborne: return sticks_centred_ ? control_state::kHovering : control_state::kFlying;
  }
  return control_state::kLanded;
}

}  // namespace labo::tello
