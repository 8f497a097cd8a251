#pragma once
// SensorModel: what the AR.Drone 2.0 reports about itself, from the true state, with its quirks:
//  - attitude from the IMU: white noise, a roll/pitch offset until a flat trim on the ground, and a
//    yaw that drifts slowly (a constant gyro bias plus a random walk; no magnetometer fusion indoors);
//  - horizontal velocity from the bottom camera (optical flow fused with the IMU), in the heading
//    frame (x forward, y left): noisy, and failing over bare floor or below ~0.3 m above the surface,
//    where it decays towards zero instead of following the motion;
//  - ultrasound altitude to the surface under the drone (floor, bench, platform: it steps at an
//    edge), sampled at 25 Hz and held, with noise, tilt and spurious short echoes; 0 on the ground;
//  - accelerometers, gyroscopes, pressure, magnetometer heading, battery and the control state.
// Every random draw happens in update() (once per physics step) from one seeded generator, so the
// same seed and the same inputs give the same readings bit for bit, however often they are read.
#include <cstdint>
#include <random>

#include "drone/emulated_vehicle.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/quadrotor_dynamics.hpp"

namespace labo::sim {

struct SensorNoise {
  double attitude_noise_rad = 0.0015;        // per sample (0.09 deg)
  double attitude_offset_rad = 0.01;         // roll/pitch offset before a flat trim (0.6 deg)
  double yaw_drift_radps = 0.0003;           // gyro bias (about 1 deg/min), sign from the seed
  double yaw_random_walk_rad_sqrt_s = 0.0005;
  double velocity_noise_mps = 0.03;
  double velocity_min_altitude_m = 0.3;      // the bottom camera's flow fails below this
  double velocity_dropout_decay_per_s = 3.0; // a failed estimate relaxes to zero
  double vz_noise_mps = 0.02;
  double ultrasound_rate_hz = 25;
  double ultrasound_noise_m = 0.01;
  double ultrasound_outlier_probability = 0.01;  // per ultrasound sample: a spurious short echo
  double ultrasound_max_range_m = 6.0;
  double gyro_noise_radps = 0.005;
  double accel_noise_mps2 = 0.05;
  double pressure_noise_pa = 2.0;
  double magneto_offset_rad = 0.3;           // the lab's steel bends the field: a fixed heading error
};

// One drone's sensor biases (a randomized world draws them, drone/sim/sim_world.hpp; none by default):
// the firmware's roll/pitch estimate off the truth after a flat trim (the firmware levels that
// estimate, so the drone flies tilted by it: QuadrotorDynamics applies the same bias), the bottom
// camera's velocity scale (its focal length and the height it divides by) and offset, the
// ultrasound's scale and offset, the gyros' and accelerometers' offsets.
struct SensorBiases {
  Eigen::Vector2d attitude_rad = Eigen::Vector2d::Zero();  // roll, pitch
  double velocity_scale = 1.0;
  Eigen::Vector2d velocity_mps = Eigen::Vector2d::Zero();  // heading frame: forward, left
  double ultrasound_scale = 1.0;
  double ultrasound_offset_m = 0.0;
  Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
};

class SensorModel {
 public:
  SensorModel(SensorNoise noise, const lab::LabDescription& lab, std::uint64_t seed, const SensorBiases& biases = {});
  // An instrument placed while the lab runs: a surface the ultrasound sees from then on.
  void add_instrument(const lab::InstrumentSpec& instrument) { lab_.instruments.push_back(instrument); }

  // Samples every sensor for the true state after a physics step of `dt`.
  void update(const QuadrotorState& truth, Seconds dt);
  // The firmware's flat trim: the roll/pitch offset is recalibrated (only on the ground).
  void flat_trim(const QuadrotorState& truth);

  const VehicleTelemetry& telemetry() const { return telemetry_; }
  // Whether the bottom camera's velocity follows the motion now (the firmware's hover uses it).
  bool velocity_valid() const { return velocity_valid_; }

 private:
  double gaussian(double sigma) { return sigma * normal_(rng_); }
  void update_attitude(const QuadrotorState& truth, Seconds dt);
  void update_velocity(const QuadrotorState& truth, Seconds dt, double height_m);
  void update_ultrasound(const QuadrotorState& truth, Seconds dt, double height_m);
  void update_inertial(const QuadrotorState& truth);

  SensorNoise noise_;
  SensorBiases biases_;
  lab::LabDescription lab_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  VehicleTelemetry telemetry_;
  double roll_offset_ = 0, pitch_offset_ = 0;
  double yaw_bias_radps_ = 0, yaw_error_ = 0;
  Eigen::Vector2d velocity_heading_ = Eigen::Vector2d::Zero();
  bool velocity_valid_ = false;
  Seconds ultrasound_age_s_ = 1e9;
  double ultrasound_m_ = 0;
};

}  // namespace labo::sim
