#include "drone/sim/sensor_model.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::sim {

using lab::LabDescription;


namespace {
constexpr double kSeaLevelPressure_pa = 101325.0;
constexpr double kPressureGradient_pa_per_m = 12.0;  // ρ·g near sea level
constexpr double kOnGround_m = 0.01;
constexpr double kShortestEcho_m = 0.15;
}  // namespace

SensorModel::SensorModel(SensorNoise noise, const LabDescription& lab, std::uint64_t seed, const SensorBiases& biases)
    : noise_(noise), biases_(biases), lab_(lab), rng_(seed) {
  roll_offset_ = gaussian(noise_.attitude_offset_rad);
  pitch_offset_ = gaussian(noise_.attitude_offset_rad);
  // A gyro bias of 0.5..1.5 times the nominal drift, either way.
  yaw_bias_radps_ = noise_.yaw_drift_radps * (0.5 + uniform_(rng_)) * (uniform_(rng_) < 0.5 ? -1.0 : 1.0);
  telemetry_.pressure_pa = kSeaLevelPressure_pa;
}

void SensorModel::flat_trim(const QuadrotorState& truth) {
  if (truth.airborne()) return;  // the firmware refuses a flat trim in flight
  roll_offset_ = gaussian(0.1 * noise_.attitude_offset_rad);
  pitch_offset_ = gaussian(0.1 * noise_.attitude_offset_rad);
}

void SensorModel::update(const QuadrotorState& truth, Seconds dt) {
  const Eigen::Vector3d& p = truth.position_m;
  const double height_m = p.z() - lab_.surface_height(p.x(), p.y());
  telemetry_.nav.t = truth.t;
  update_attitude(truth, dt);
  update_velocity(truth, dt, height_m);
  update_ultrasound(truth, dt, height_m);
  update_inertial(truth);
}

void SensorModel::update_attitude(const QuadrotorState& truth, Seconds dt) {
  yaw_error_ += yaw_bias_radps_ * dt + gaussian(noise_.yaw_random_walk_rad_sqrt_s * std::sqrt(dt));
  NavdataSample& nav = telemetry_.nav;
  nav.roll_rad = truth.roll_rad + roll_offset_ + biases_.attitude_rad.x() + gaussian(noise_.attitude_noise_rad);
  nav.pitch_rad = truth.pitch_rad + pitch_offset_ + biases_.attitude_rad.y() + gaussian(noise_.attitude_noise_rad);
  nav.yaw_rad = wrap_angle(truth.yaw_rad + yaw_error_ + gaussian(noise_.attitude_noise_rad));
}

void SensorModel::update_velocity(const QuadrotorState& truth, Seconds dt, double height_m) {
  NavdataSample& nav = telemetry_.nav;
  if (!truth.airborne()) {
    velocity_heading_.setZero();
    velocity_valid_ = false;
    nav.vx_mps = nav.vy_mps = nav.vz_mps = 0;
    return;
  }
  const Eigen::Vector3d& p = truth.position_m;
  const bool over_floor = lab_.surface_height(p.x(), p.y()) <= lab_.room.min.z() + 1e-9;
  velocity_valid_ = height_m >= noise_.velocity_min_altitude_m && !(over_floor && lab_.floor_is_bare(p.x(), p.y()));
  if (velocity_valid_) {
    const double c = std::cos(truth.yaw_rad), s = std::sin(truth.yaw_rad);
    const Eigen::Vector3d& v = truth.velocity_mps;
    velocity_heading_ = biases_.velocity_scale * Eigen::Vector2d(c * v.x() + s * v.y(), -s * v.x() + c * v.y()) +
                        biases_.velocity_mps;
  } else {
    velocity_heading_ *= std::exp(-noise_.velocity_dropout_decay_per_s * dt);
  }
  nav.vx_mps = velocity_heading_.x() + gaussian(noise_.velocity_noise_mps);
  nav.vy_mps = velocity_heading_.y() + gaussian(noise_.velocity_noise_mps);
  nav.vz_mps = truth.velocity_mps.z() + gaussian(noise_.vz_noise_mps);
}

void SensorModel::update_ultrasound(const QuadrotorState& truth, Seconds dt, double height_m) {
  ultrasound_age_s_ += dt;
  const Seconds period = 1.0 / noise_.ultrasound_rate_hz;
  if (!truth.airborne()) {
    ultrasound_m_ = 0;  // the firmware reports 0 on the ground
  } else if (ultrasound_age_s_ + 1e-12 < period) {
    return;  // the sonar holds its last echo between pings
  } else if (height_m < kOnGround_m) {
    ultrasound_age_s_ = 0;
    ultrasound_m_ = 0;
  } else {
    ultrasound_age_s_ = 0;
    // The sonar looks along the body's -z: a tilted drone measures a slant range.
    double range = biases_.ultrasound_scale * height_m / std::max(0.5, std::cos(truth.roll_rad) * std::cos(truth.pitch_rad)) +
                   biases_.ultrasound_offset_m + gaussian(noise_.ultrasound_noise_m);
    if (uniform_(rng_) < noise_.ultrasound_outlier_probability) {
      range = kShortestEcho_m + uniform_(rng_) * std::max(0.0, range - kShortestEcho_m);
    }
    ultrasound_m_ = std::clamp(range, 0.0, noise_.ultrasound_max_range_m);
  }
  telemetry_.nav.altitude_m = ultrasound_m_;
}

void SensorModel::update_inertial(const QuadrotorState& truth) {
  const Eigen::Matrix3d R = rotation_from_ypr(truth.yaw_rad, truth.pitch_rad, truth.roll_rad);
  // Specific force: what the accelerometers feel (1 g up at rest), in the body frame.
  const Eigen::Vector3d gravity(0, 0, 9.80665);
  telemetry_.accel_body_mps2 = R.transpose() * (truth.acceleration_mps2 + gravity) + biases_.accel_mps2;
  telemetry_.gyro_body_radps = truth.angular_velocity_body_radps + biases_.gyro_radps;
  for (int i = 0; i < 3; ++i) {
    telemetry_.accel_body_mps2[i] += gaussian(noise_.accel_noise_mps2);
    telemetry_.gyro_body_radps[i] += gaussian(noise_.gyro_noise_radps);
  }
  telemetry_.pressure_pa =
      kSeaLevelPressure_pa - kPressureGradient_pa_per_m * truth.position_m.z() + gaussian(noise_.pressure_noise_pa);
  telemetry_.magneto_heading_rad =
      wrap_angle(truth.yaw_rad + noise_.magneto_offset_rad + gaussian(10 * noise_.attitude_noise_rad));
}

}  // namespace labo::sim
