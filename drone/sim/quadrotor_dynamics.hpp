#pragma once
// QuadrotorDynamics: the simulated lab's plant, the AR.Drone 2.0 as a rigid body (Airframe: mass,
// inertia, rotor thrust and drag torque, rotor and air drag, ground effect) with its motors and
// battery (Propulsion: spin-up lag, voltage sag) under a model of its firmware: the inner loops
// (FirmwareLoops: attitude, yaw rate, vertical speed, with their own lags and saturation) and the
// firmware's behaviour around them, within its configured limits (euler_angle_max, control_vz_max,
// control_yaw, altitude_max):
//  - PCMD: roll and pitch set points = command × euler_angle_max, yaw rate = command × control_yaw,
//    vertical speed = command × control_vz_max;
//  - take-off (spin-up, then a climb to about 1 m above the surface it started from), landing (a
//    descent to touch-down), firmware hover (PCMD flag 0, or no command for 2 s: brake with the
//    bottom camera's velocity when it sees the floor, hold the height), altitude limits above the
//    surface below, battery drain, and a crash (motors cut, the drone falls) when the hull touches a
//    wall, the ceiling, a bench, an instrument or the teacher.
// The firmware knows the nominal drone (`QuadrotorParams`); the drone it flies may differ from it by
// `PlantDeviation` (a randomized world draws one per seed: drone/sim/sim_world.hpp). Not the
// estimator's prediction model (first-order closed-loop lags, localization/estimation/drone_ekf.hpp):
// its nominal responses are close to that model's fitted constants, its structure is not.
// Deterministic: the firmware runs once per fixed step, the rigid body in fixed sub-steps; commands
// act from the next step.
//
// Pose: the body origin is the hull's underside centre (world frame, z up); yaw, pitch, roll as in
// core/frames.hpp (pitch > 0 nose down, roll > 0 right side down, yaw counter-clockwise).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "core/time.hpp"
#include "drone/drone_link.hpp"
#include "drone/sim/airframe.hpp"
#include "drone/sim/collision_model.hpp"
#include "drone/sim/firmware_loops.hpp"
#include "drone/sim/propulsion.hpp"

namespace labo::sim {

// How the drone differs from the nominal one its firmware assumes (the identity in the nominal world).
struct PlantDeviation {
  double mass_factor = 1.0;           // mass and inertia
  double rotor_drag_factor = 1.0;
  double air_drag_factor = 1.0;
  double motor_lag_factor = 1.0;      // the inner loops' time constants: the motors' spin-up,
  double attitude_lag_factor = 1.0;   // the attitude loop (1 / attitude_loop_per_s),
  double yaw_lag_factor = 1.0;        // the yaw-rate loop (1 / yaw_rate_loop_per_s),
  double vertical_lag_factor = 1.0;   // the vertical-speed set point's shaping (1 / vz_reference_per_s)
  std::array<double, 4> rotor_efficiency{1.0, 1.0, 1.0, 1.0};
  // The firmware's roll, pitch estimate minus the truth (SimulatedLab sets it from the sensors' bias).
  Eigen::Vector2d attitude_bias_rad = Eigen::Vector2d::Zero();
};

struct QuadrotorParams {
  Seconds step_s = 0.005;                 // the firmware's period
  int substeps = 5;                       // rigid-body sub-steps per firmware period
  double tilt_max_rad = 0.2094;           // control:euler_angle_max (12 deg)
  double yaw_rate_max_radps = 1.7453;     // control:control_yaw (100 deg/s)
  double vz_max_mps = 0.7;                // control:control_vz_max
  double takeoff_height_m = 1.0;          // above the surface the drone took off from
  Seconds takeoff_spinup_s = 0.5;         // motors spin up before the drone lifts
  double landing_speed_mps = 0.5;
  double altitude_max_m = 3.0;            // control:altitude_max, above the surface below
  double altitude_min_m = 0.25;           // in flight the firmware does not descend below this
  Seconds command_timeout_s = 2.0;        // no PCMD for this long: firmware hover
  double hover_velocity_gain_per_s = 2.0; // firmware hover: desired deceleration per m/s
  // The firmware's own height control (take-off, hover, altitude window): a PD on height into the
  // vertical-speed loop, placed at this bandwidth and damping for its set-point shaping.
  double height_hold_bandwidth_radps = 1.5;
  double height_hold_damping = 0.9;
  AirframeParams airframe;                // the nominal drone, as the firmware assumes it
  RotorParams rotors;
  FirmwareLoopParams loops;
  BatteryParams battery;
  PlantDeviation deviation;               // the drone actually flown
  HullShape hull;
};

enum class FirmwarePhase { Landed, TakingOff, Flying, Hovering, Landing, Emergency };
// The navdata major control state: 2 landed, 6 take-off, 3 flying, 4 hovering, 8 landing; an
// emergency reports landed with the emergency bit.
int to_control_state(FirmwarePhase phase);
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
  double battery_voltage_v = 0;       // under the present load
  std::string crash_reason;           // what the hull hit (empty: no crash)
  int crashes = 0;

  Eigen::Isometry3d T_world_body() const;
  bool airborne() const;
};

// The drone actually flown: the nominal parameters with the deviation applied.
AirframeParams deviated_airframe(const QuadrotorParams& p);
RotorParams deviated_rotors(const QuadrotorParams& p);
FirmwareLoopParams deviated_loops(const QuadrotorParams& p);

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

  // Disturbances: a velocity change (world, m/s) and a turn about the vertical by `dyaw_rad`, at once
  // (the yaw-rate loop then holds the new heading); a steady wind.
  void push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad);
  void set_wind(const Eigen::Vector3d& wind_world_mps) { wind_ = wind_world_mps; }
  // Whether the firmware sees the floor's texture this step (its hover brakes on that velocity).
  void set_velocity_observable(bool observable) { velocity_observable_ = observable; }
  CollisionModel& collision() { return collision_; }

  // One fixed step of params().step_s.
  void step();
  const QuadrotorState& state() const { return s_; }
  const QuadrotorParams& params() const { return p_; }
  // Each rotor's thrust now (N), for tests and diagnostics.
  const RotorThrusts& rotor_thrust() const { return propulsion_.thrust(); }

 private:
  FirmwareSetpoints firmware_hover_targets() const;
  FirmwareSetpoints targets();
  void update_phase();
  void fly();
  void rest_on(double support);
  void refresh_state(const Eigen::Vector3d& v_before);
  void contact_and_collisions();
  void fall();
  double height_above_surface() const;
  // The vertical-speed reference that brings the underside to `target_z` (world).
  double height_hold_vz(double target_z) const;

  QuadrotorParams p_;
  Airframe airframe_;
  Propulsion propulsion_;
  FirmwareLoops loops_;
  CollisionModel collision_;
  RigidBodyState body_;
  QuadrotorState s_;
  double height_kp_, height_kd_;  // height_hold_vz's gains
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

}  // namespace labo::sim
