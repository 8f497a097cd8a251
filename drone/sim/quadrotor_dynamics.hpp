#pragma once
// QuadrotorDynamics: the AR.Drone 2.0 as its firmware makes it fly, for the simulated lab. Not a
// rotor-level model: the firmware's inner loops are represented by their closed-loop response, the
// model tum_ardrone fitted on the real drone (../shared/notes/tum_ardrone.md §1), with the limits of
// the firmware's configuration (euler_angle_max, control_vz_max, control_yaw, altitude_max):
//  - roll and pitch follow the PCMD command × euler_angle_max with a first-order lag (7 /s);
//  - the thrust holds the height, so the horizontal acceleration is g·(tilted thrust direction) minus
//    linear drag (0.58 /s) on the velocity relative to the air;
//  - the yaw rate follows the command × control_yaw (25 /s), the vertical speed the command ×
//    control_vz_max (0.8 /s);
//  - take-off (spin-up, then a climb to about 1 m above the surface it started from), landing (a
//    descent to touch-down), firmware hover (PCMD flag 0, or no command for 2 s: brake with the
//    bottom camera's velocity when it sees the floor, hold the height), altitude limits above the
//    surface below, battery drain, and a crash (motors cut, the drone falls) when the hull touches a
//    wall, the ceiling, a bench, an instrument or the teacher.
// Deterministic: a fixed internal step; commands act from the next step.
//
// Pose: the body origin is the hull's underside centre (world frame, z up); yaw, pitch, roll as in
// core/frames.hpp (pitch > 0 nose down, roll > 0 right side down, yaw counter-clockwise).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "drone/sim/collision_model.hpp"

namespace labo {

struct QuadrotorParams {
  Seconds step_s = 0.005;
  double tilt_max_rad = 0.2094;           // control:euler_angle_max (12 deg)
  double attitude_rate_per_s = 7.0;       // roll/pitch lag (tum c3)
  double yaw_rate_max_radps = 1.7453;     // control:control_yaw (100 deg/s)
  double yaw_response_per_s = 25.0;       // yaw-rate lag (tum c5)
  double vz_max_mps = 0.7;                // control:control_vz_max
  double vertical_response_per_s = 0.8;   // vertical-speed lag (tum c7)
  double drag_per_s = 0.58;               // horizontal linear drag (tum c1)
  double gravity_mps2 = 9.80665;
  double takeoff_height_m = 1.0;          // above the surface the drone took off from
  Seconds takeoff_spinup_s = 0.5;         // motors spin up before the drone lifts
  double landing_speed_mps = 0.5;
  double altitude_max_m = 3.0;            // control:altitude_max, above the surface below
  double altitude_min_m = 0.25;           // in flight the firmware does not descend below this
  Seconds command_timeout_s = 2.0;        // no PCMD for this long: firmware hover
  double hover_velocity_gain_per_s = 2.0; // firmware hover: desired deceleration per m/s
  // The firmware's own height control (take-off, hover, altitude window): a PD on height through the
  // same vertical-speed lag, tuned to this bandwidth and damping.
  double height_hold_bandwidth_radps = 1.5;
  double height_hold_damping = 0.9;
  HullShape hull;
  double battery_start_percent = 95.0;
  double battery_flying_drain_percent_per_s = 0.125;  // about 13 minutes of flight
  double battery_idle_drain_percent_per_s = 0.005;
  double battery_low_percent = 20.0;      // state bit 15; at 0 the firmware lands
};

enum class FirmwarePhase { Landed, TakingOff, Flying, Hovering, Landing, Emergency };
// The navdata major control state: 2 landed, 6 take-off, 3 flying, 4 hovering, 8 landing; an
// emergency reports landed with the emergency bit.
int control_state(FirmwarePhase phase);
std::string to_string(FirmwarePhase phase);

// The true state (ground truth).
struct QuadrotorState {
  Seconds t = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();    // hull underside centre, world
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  // world
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();  // world, over the last step
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;
  double yaw_rate_radps = 0;  // d(yaw)/dt
  Eigen::Vector3d angular_velocity_body_radps = Eigen::Vector3d::Zero();
  FirmwarePhase phase = FirmwarePhase::Landed;
  bool hovering_by_firmware = false;  // PCMD flag 0 or command timeout
  double battery_percent = 100;
  std::string crash_reason;           // what the hull hit (empty: no crash)
  int crashes = 0;

  Eigen::Isometry3d T_world_body() const;
  bool airborne() const;
};

class QuadrotorDynamics {
 public:
  // Starts landed at `T_world_start` (its translation is the underside, on the surface below).
  QuadrotorDynamics(QuadrotorParams params, CollisionModel collision, const Eigen::Isometry3d& T_world_start);

  // Commands act at the current simulated time (state().t).
  void takeoff();
  void land();
  void emergency();  // the REF emergency toggle: cuts the motors, or clears an emergency on the ground
  // `hover` = PCMD flag bit 0 clear.
  void move(const MoveCommand& command, bool hover);

  // Disturbances: a velocity change (world, m/s) and a yaw kick that turns the drone by about
  // `dyaw_rad` before the yaw-rate loop absorbs it, at once; a steady wind.
  void push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad);
  void set_wind(const Eigen::Vector3d& wind_world_mps) { wind_ = wind_world_mps; }
  // Whether the firmware sees the floor's texture this step (its hover brakes on that velocity).
  void set_velocity_observable(bool observable) { velocity_observable_ = observable; }
  CollisionModel& collision() { return collision_; }

  // One fixed step of params().step_s.
  void step();
  const QuadrotorState& state() const { return s_; }
  const QuadrotorParams& params() const { return p_; }

 private:
  struct Targets {
    double roll = 0, pitch = 0, yaw_rate = 0, vz = 0;
  };
  Targets firmware_hover_targets() const;
  Targets targets();
  void update_phase();
  void integrate(const Targets& ref);
  void contact_and_collisions();
  void fall();
  void drain_battery();
  double height_above_surface() const;
  // The vertical-speed reference that brings the underside to `target_z` (world).
  double height_hold_vz(double target_z) const;

  QuadrotorParams p_;
  CollisionModel collision_;
  QuadrotorState s_;
  double attitude_alpha_, yaw_alpha_, vertical_alpha_;  // exact first-order factors for one step
  double height_kp_, height_kd_;                         // height_hold_vz's gains
  std::int64_t steps_ = 0;
  MoveCommand command_;
  bool hover_flag_ = true;
  Seconds last_command_t_ = -1e9;
  Seconds phase_start_t_ = 0;
  double takeoff_target_z_ = 0;
  double hold_z_ = 0;
  bool holding_ = false;
  bool velocity_observable_ = true;
  Eigen::Vector3d wind_ = Eigen::Vector3d::Zero();
};

}  // namespace labo
