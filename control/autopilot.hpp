#pragma once
// The autopilot: the flight phase (landed, taking off, flying, landing, emergency) and, while flying,
// a pose target flown with the PID PoseController, with tum_ardrone's waypoint criteria: reached
// when closer than reach_distance_m with the yaw within reach_yaw_rad, done after staying within
// stay_distance_m for stay_time_s. Every target is clamped into the geofence. Phase changes follow
// the navdata's control state (2 landed, 3/4 flying, 6 take-off, 8 landing) with time-outs.
#include <optional>

#include "control/control_config.hpp"
#include "control/flight_types.hpp"
#include "control/geofence.hpp"
#include "control/pid_controller.hpp"

namespace labo::control {

class Autopilot {
 public:
  Autopilot(const ControlConfig& config, Geofence fence);

  // Phase commands; each returns the action to send once.
  FlightOutput takeoff(Seconds t);
  FlightOutput land(Seconds t);
  FlightOutput emergency(Seconds t);
  void on_control_state(int control_state, Seconds t);

  // Targets (world, clamped into the fence). `new_waypoint` false: a moving set point (trajectory),
  // the integrals and the reach/stay clocks are kept.
  void go_to(const PoseTarget& target, Seconds t, bool new_waypoint = true);
  void hold_here(const fusion::PoseEstimate& pose, Seconds t);  // target = current pose
  void clear_target() { target_.reset(); }

  FlightOutput step(const fusion::PoseEstimate& pose, Seconds t);

  FlightPhase phase() const { return phase_; }
  bool flying() const { return phase_ == FlightPhase::Flying; }
  const std::optional<PoseTarget>& target() const { return target_; }
  bool reached() const { return reached_; }
  bool done() const { return done_; }  // reached and stayed for stay_time_s
  double distance_to_target() const { return distance_; }
  const Geofence& fence() const { return fence_; }
  const MoveCommand& last_command() const { return last_command_; }

 private:
  void update_criteria(const fusion::PoseEstimate& pose, Seconds t);

  ControlConfig config_;
  Geofence fence_;
  PoseController controller_;
  FlightPhase phase_ = FlightPhase::Landed;
  Seconds phase_since_ = 0;
  std::optional<PoseTarget> target_;
  Seconds last_step_t_ = -1;
  bool reached_ = false;
  bool done_ = false;
  Seconds within_since_ = -1;
  double distance_ = 0;
  MoveCommand last_command_;
};

}  // namespace labo::control
