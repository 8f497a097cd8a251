#pragma once
// The Tello's state string carries no flight state, but NavdataSample::control_state is how the rest
// of LaboDrone knows whether the drone is landed, taking off, flying or landing (the AR.Drone's
// numbers: 2 landed, 3 flying, 4 hovering, 6 take-off, 8 landing). TelloFlightPhase keeps that
// account from what the link sent, what the drone answered and whether its motors run (the state's
// `time`, the motors' running time in whole seconds, grows only while they do). So a landing the link
// did not ask for (the drone's 15 s watchdog, a low battery) and a flight already under way when the
// link connects are both noticed. No I/O, no clock: every call takes its time.
#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "drone/tello/tello_command.hpp"
#include "drone/tello/tello_state.hpp"

namespace labo::tello {

class TelloFlightPhase {
 public:
  // `motors_off_after_s`: the motors' time unchanged this long means they stopped (it ticks each second).
  explicit TelloFlightPhase(Seconds motors_off_after_s = 2.5) : motors_off_after_s_(motors_off_after_s) {}

  // A command went out (takeoff, land, emergency change the phase; others do not).
  void on_sent(std::string_view command, Seconds t);
  // A command ended (its reply, or none in time).
  void on_outcome(const CommandOutcome& outcome, Seconds t);
  // A state string was accepted.
  void on_state(const TelloState& state, Seconds t);
  // The sticks the link streams: centred = hovering, else flying.
  void on_sticks(bool centred) { sticks_centred_ = centred; }

  int control_state() const;
  bool airborne() const { return phase_ != Phase::Landed; }
  // Landings the link did not command (seen as the motors stopping), since the start.
  int unexpected_landings() const { return unexpected_landings_; }

 private:
  enum class Phase { Landed, TakingOff, Airborne, Landing };
  bool motors_running(Seconds t) const { return motors_seen_t_ >= 0 && t - motors_changed_t_ < motors_off_after_s_; }

  Seconds motors_off_after_s_;
  Phase phase_ = Phase::Landed;
  bool sticks_centred_ = true;
  double motors_s_ = -1;          // the last `time` value
  Seconds motors_seen_t_ = -1;    // when a state was last seen
  Seconds motors_changed_t_ = -1e9;  // when `time` last grew
  int unexpected_landings_ = 0;
  int growths_while_landed_ = 0;
};

}  // namespace labo::tello
