#include "drone/sim/firmware_loops.hpp"

#include <algorithm>
#include <cmath>

namespace labo::sim {

namespace {
double follow(double rate_per_s, Seconds dt) { return 1.0 - std::exp(-rate_per_s * dt); }
}  // namespace

FirmwareLoops::FirmwareLoops(const FirmwareLoopParams& params, const AirframeParams& airframe, const RotorParams& rotors)
    : p_(params), assumed_(airframe), rotors_(rotors), unmix_(Airframe(airframe).mixer().inverse()) {}

void FirmwareLoops::reset() {
  vz_reference_ = vz_sensed_ = vz_integral_ = 0;
  rate_integral_.setZero();
}

RotorThrusts FirmwareLoops::update(const FirmwareSetpoints& set, const FirmwareSensing& sensed, Seconds dt) {
  // Vertical speed: shaped set point, lagging estimate, PI to a vertical acceleration.
  vz_sensed_ += follow(1.0 / p_.vz_sensing_lag_s, dt) * (sensed.vz_mps - vz_sensed_);
  vz_reference_ += follow(p_.vz_reference_per_s, dt) * (set.vz_mps - vz_reference_);
  const double vz_error = vz_reference_ - vz_sensed_;
  vz_integral_ = std::clamp(vz_integral_ + p_.vz_integral_per_s2 * vz_error * dt, -p_.vz_integral_limit_mps2,
                            p_.vz_integral_limit_mps2);
  const double sr = std::sin(sensed.roll_rad), cr = std::cos(sensed.roll_rad);
  const double sp = std::sin(sensed.pitch_rad), cp = std::cos(sensed.pitch_rad);
  const double collective =
      assumed_.mass_kg * (assumed_.gravity_mps2 + p_.vz_loop_per_s * vz_error + vz_integral_) / std::max(0.5, cr * cp);

  // Attitude: angle errors to Euler-rate set points, then to body rates (Z-Y-X kinematics).
  const double roll_rate = std::clamp(p_.attitude_loop_per_s * (set.roll_rad - sensed.roll_rad), -p_.tilt_rate_max_radps,
                                      p_.tilt_rate_max_radps);
  const double pitch_rate = std::clamp(p_.attitude_loop_per_s * (set.pitch_rad - sensed.pitch_rad),
                                       -p_.tilt_rate_max_radps, p_.tilt_rate_max_radps);
  const double yaw_rate = set.yaw_rate_radps;
  const Eigen::Vector3d rates_set(roll_rate - yaw_rate * sp, pitch_rate * cr + yaw_rate * cp * sr,
                                  -pitch_rate * sr + yaw_rate * cp * cr);
  const Eigen::Vector3d error = rates_set - sensed.rates_body_radps;
  const Eigen::Vector3d gain(p_.rate_loop_per_s, p_.rate_loop_per_s, p_.yaw_rate_loop_per_s);
  const Eigen::Vector3d integral_gain(p_.rate_integral_per_s2, p_.rate_integral_per_s2, p_.yaw_rate_integral_per_s2);
  Eigen::Vector3d integral = (rate_integral_ + integral_gain.cwiseProduct(error) * dt)
                                 .cwiseMax(-p_.rate_integral_limit_radps2)
                                 .cwiseMin(p_.rate_integral_limit_radps2);
  double yaw_share = 1.0;
  const RotorThrusts thrust =
      allocate(collective, assumed_.inertia_kgm2.cwiseProduct(gain.cwiseProduct(error) + integral), yaw_share);
  if (yaw_share < 1.0) integral.z() = rate_integral_.z();  // no wind-up while the yaw torque gives way
  rate_integral_ = integral;
  return thrust;
}

RotorThrusts FirmwareLoops::allocate(double collective_n, const Eigen::Vector3d& torque_nm, double& share) const {
  const Eigen::Vector4d base = unmix_ * Eigen::Vector4d(collective_n, torque_nm.x(), torque_nm.y(), 0.0);
  const Eigen::Vector4d yaw = unmix_ * Eigen::Vector4d(0.0, 0.0, 0.0, torque_nm.z());
  // The largest share of the yaw torque that keeps every rotor in range (none if one already is not).
  share = 1.0;
  for (int i = 0; i < 4; ++i) {
    const double room = yaw(i) > 0 ? rotors_.max_thrust_n - base(i) : base(i) - rotors_.min_thrust_n;
    if (std::abs(yaw(i)) > 1e-12) share = std::min(share, std::max(0.0, room / std::abs(yaw(i))));
  }
  RotorThrusts thrust{};
  for (int i = 0; i < 4; ++i) {
    thrust[static_cast<std::size_t>(i)] = std::clamp(base(i) + share * yaw(i), rotors_.min_thrust_n, rotors_.max_thrust_n);
  }
  return thrust;
}

}  // namespace labo::sim
