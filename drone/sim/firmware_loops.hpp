#pragma once
// FirmwareLoops: the AR.Drone 2.0 firmware's inner loops, as the simulated lab's plant runs them on
// the rigid body (Airframe, Propulsion), once per firmware period. Not a closed-loop response fitted to
// the real drone (the estimator's model family, localization/estimation/drone_ekf.hpp) but the
// cascade that produces one, with its own lags and limits:
//  - attitude: the roll/pitch set point error times `attitude_loop_per_s` gives a rate set point
//    (limited to `tilt_rate_max_radps`); with the yaw-rate set point it becomes body rates, which a PI
//    loop on the gyros turns into angular accelerations, torques through the inertia the firmware
//    assumes;
//  - vertical speed: the set point is shaped by a first-order filter (`vz_reference_per_s`), then a PI
//    loop on the firmware's own vertical speed (which lags the truth by `vz_sensing_lag_s`) gives a
//    vertical acceleration, a collective thrust through the mass the firmware assumes, divided by the
//    tilt's cosine;
//  - the mixer of the airframe the firmware assumes turns thrust and torques into four rotor thrusts,
//    within the motors' range; when a rotor would leave it, the yaw torque gives way first.
// The firmware knows the nominal drone only: a heavier drone, a sagging battery or a weak rotor are
// for its integrators to find.
#include <Eigen/Core>

#include "core/time.hpp"
#include "drone/sim/airframe.hpp"
#include "drone/sim/propulsion.hpp"

namespace labo::sim {

struct FirmwareLoopParams {
  double attitude_loop_per_s = 7.5;       // roll/pitch error → rate set point
  double tilt_rate_max_radps = 3.5;       // about 200 deg/s
  double rate_loop_per_s = 20.0;          // roll/pitch rate error → angular acceleration
  double rate_integral_per_s2 = 20.0;
  double yaw_rate_loop_per_s = 20.0;      // yaw-rate error → angular acceleration
  double yaw_rate_integral_per_s2 = 5.0;
  double rate_integral_limit_radps2 = 30.0;
  double vz_reference_per_s = 0.85;       // the vertical-speed set point's shaping
  double vz_loop_per_s = 8.0;             // vertical-speed error → vertical acceleration
  double vz_integral_per_s2 = 8.0;
  double vz_integral_limit_mps2 = 4.0;
  double vz_sensing_lag_s = 0.03;         // the firmware's vertical speed behind the truth
};

// What the firmware is asked to hold: roll and pitch (rad), yaw rate (rad/s), vertical speed (m/s).
struct FirmwareSetpoints {
  double roll_rad = 0, pitch_rad = 0, yaw_rate_radps = 0, vz_mps = 0;
};

// What the firmware senses: its attitude estimate, the gyros (body rates) and the vertical speed.
struct FirmwareSensing {
  double roll_rad = 0, pitch_rad = 0;
  Eigen::Vector3d rates_body_radps = Eigen::Vector3d::Zero();
  double vz_mps = 0;
};

class FirmwareLoops {
 public:
  // `airframe` and `rotors` are what the firmware assumes the drone is (the nominal drone).
  FirmwareLoops(const FirmwareLoopParams& params, const AirframeParams& airframe, const RotorParams& rotors);

  // One firmware period of `dt`: the rotor thrusts it demands.
  RotorThrusts update(const FirmwareSetpoints& set, const FirmwareSensing& sensed, Seconds dt);
  // Motors off on the ground: integrators and filters start again from rest.
  void reset();
  const FirmwareLoopParams& params() const { return p_; }

 private:
  // `share`: how much of the yaw torque fitted (1: all of it).
  RotorThrusts allocate(double collective_n, const Eigen::Vector3d& torque_nm, double& share) const;

  FirmwareLoopParams p_;
  AirframeParams assumed_;
  RotorParams rotors_;
  Eigen::Matrix4d unmix_;  // inverse of the assumed airframe's mixer
  double vz_reference_ = 0, vz_sensed_ = 0, vz_integral_ = 0;
  Eigen::Vector3d rate_integral_ = Eigen::Vector3d::Zero();
};

}  // namespace labo::sim
