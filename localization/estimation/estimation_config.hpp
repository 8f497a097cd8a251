#pragma once
// Configuration of the state estimator: link delays, the AR.Drone motion-model constants (refitted on
// the simulated lab, docs/state-estimation.md), measurement noise, gates and source switching. Read
// from the "estimation" section of the config by read_estimation_config; the paper's vision
// thresholds D, beta and gamma come from the "vision" section (VisionThresholds).
#include "core/config_reader.hpp"
#include "core/time.hpp"
#include "localization/estimation/reacquisition_gate.hpp"
#include "localization/estimation/scale_estimator.hpp"

namespace labo::estimation {

// First-order responses of the AR.Drone's onboard controllers to the normalized PCMD (MoveCommand):
//   roll'    = attitude_rate_hz * (tilt_max_rad * u_roll  - roll)      (pitch alike)
//   yawrate' = yaw_response_hz  * (yaw_rate_max_radps * u_yaw - yawrate)
//   vz'      = vertical_response_hz * (vz_max_mps * u_gaz - vz)
//   a_h      = thrust_accel_mps2 * f_h(roll, pitch, yaw) - drag_per_s * v_h
// where f_h is the horizontal part of the body z axis in the world.
struct MotionModelConstants {
  double attitude_rate_hz = 7.0;
  double tilt_max_rad = 0.21;
  double yaw_response_hz = 5.0;
  double yaw_rate_max_radps = 1.75;
  double vertical_response_hz = 3.0;
  double vz_max_mps = 0.7;
  double thrust_accel_mps2 = 9.81;
  double drag_per_s = 0.55;
};

struct EstimatorNoise {
  // Process noise densities (white, continuous).
  double accel_xy_mps2 = 1.0;
  double accel_z_mps2 = 0.8;
  double attitude_radps = 0.3;
  double yaw_accel_radps2 = 1.5;
  // Navdata.
  double attitude_obs_rad = 0.01;       // roll/pitch
  double yaw_increment_rad = 0.01;
  double velocity_mps = 0.05;           // bottom camera, without vision
  double velocity_with_vision_mps = 0.15;
  double vertical_velocity_mps = 0.08;  // navdata vz
  double ultrasound_m = 0.02;
  // Vision (per fused frame).
  double slam_position_m = 0.03;
  double slam_yaw_rad = 0.02;
  double object_position_m = 0.02;
  double object_yaw_rad = 0.02;
  double face_position_m = 0.04;
  double face_yaw_rad = 0.05;
  double survey_position_m = 0.05;      // lab.json object poses
  // How far a lab.json orientation (facing_deg, tilt_deg) may be off. A planar object's orientation
  // measured from a few metres is worse than that (the face-on tilt of a 60 px panel: degrees), so
  // placements weigh rotations by their own variances, not by the position's (docs/state-estimation.md).
  double survey_rotation_rad = 0.05;
};

// Detection of a failed bottom-camera velocity (velocity_dropout_detector.hpp; thresholds chosen on
// the simulated lab, docs/state-estimation.md "Velocity dropout").
struct VelocityDropoutSettings {
  bool enabled = true;          // false fuses every navdata velocity (no detection, for comparison)
  Seconds window_s = 0.4;       // the model-consistency window
  Seconds average_s = 0.1;      // the measured velocity is averaged over this span at both ends
  double onset_mps = 0.1;       // speed lost against the model over the window
  double onset_ratio = 0.6;     // ... and the measured speed below this share of the model's
  double alive_mps = 0.1;       // a failed flow reads about zero; above this it may follow the motion
  double agree_mps = 0.06;      // measured vs the filter's model-propagated velocity, to resume at rest
  int confirm_packets = 2;      // consecutive packets a verdict needs
  // While in dropout the filter runs on the model; its horizontal acceleration noise (m/s^2/sqrt(Hz))
  // is this instead of noise.accel_xy_mps2, which is tuned for fused velocities.
  double dropout_accel_noise_mps2 = 0.3;
};

// A bound on how far dead reckoning has drifted since the last fix on the lab's frame. The EKF's
// covariance treats the navdata velocity's error as white, so it averages away over hundreds of
// packets; the bottom camera's real error is a slow bias and a scale error, and integrated they grow
// with time and distance flown. The bound is per horizontal axis. These are the sensor's accuracy as specified for a deployment, not
// fitted to any flight.
struct DriftBoundSettings {
  double velocity_bias_mps = 0.02;  // bias of the navdata's horizontal velocity, each axis
  double velocity_scale = 0.05;     // its scale error, a fraction of the speed
  double dropout_mps = 0.10;        // added while the velocity is in dropout (the model's guess)
};

struct EstimatorConfig {
  Seconds video_delay_s = 0.075;
  Seconds navdata_delay_s = 0.040;
  Seconds control_delay_s = 0.100;
  // How long the persistent filter waits for late vision results before it moves on with navdata
  // only (a vision result older than the filter is then rejected as late).
  Seconds vision_latency_allowance_s = 0.25;
  // Timestamps more than this ahead of the newest navdata are refused as far-future; a navdata packet
  // that far ahead is taken when the next one confirms it (the link back after a gap).
  Seconds max_future_s = 1.0;
  // After the link goes silent the drone's firmware flies the last command it received this long,
  // then hovers (the AR.Drone's com watchdog, `general:com_watchdog`, 2 s by default).
  Seconds firmware_command_hold_s = 2.0;
  // ... and its hover holds the drone still on its own velocity estimate (the bottom camera's): the
  // horizontal velocity dies away with this time constant. Nothing in the navdata shows it while the
  // link is down, so the gap is dead reckoned on it; coasting on the tilt model instead carried a
  // 1 m/s drone 4-6 m on across an 8-s cut (docs/state-estimation.md).
  Seconds firmware_hover_stop_s = 1.0;
  MotionModelConstants model;
  EstimatorNoise noise;
  // Source switching: a source drives the estimate after `source_enter_count` consecutive accepted
  // frames and stops after `source_timeout_s` without one.
  int source_enter_count = 3;
  Seconds source_timeout_s = 0.4;
  // Vision residual gate (Mahalanobis distance^2, 4 dof) once a source is established.
  double vision_gate_chi2 = 40.0;
  // A source's first poses after a loss, against the dead-reckoned estimate (reacquisition_gate.hpp).
  ReacquisitionSettings reacquisition;
  // A vision source that does not drive the estimate is fused with its noise times this factor.
  double inactive_source_noise_factor = 3.0;
  // Fuse the navdata's vertical speed (the AR.Drone's observer; 0 in some firmwares' demo mode).
  bool use_navdata_vz = true;
  // false reproduces the paper's ultrasound rule (increments above gamma dropped as floor steps), for
  // comparison in the experiments; true tells pushes from floor steps (altitude_tracker.hpp).
  bool altitude_step_discrimination = true;
  VelocityDropoutSettings velocity_dropout;
  DriftBoundSettings drift_bound;
  // Scale estimation (tum_ardrone's ML estimator; ScaleSettings in scale_estimator.hpp for what
  // differs). Noises are per pair and in metres after the axis weights; config keys scale_sigma_map_m,
  // scale_sigma_metric_m, scale_min_displacement_m, scale_memory_pairs, scale_outlier_chi2 and
  // initial_scale.
  ScaleSettings scale;
  Seconds scale_interval_min_s = 1.0;
  Seconds scale_interval_max_s = 3.0;
  // A pair whose odometry saw a longer navdata interval is not used (scale_pair_sampler.hpp): 1.5
  // periods of the telemetry (the AR.Drone's 15 Hz demo navdata; a Tello's 10 Hz state: 0.15).
  Seconds scale_max_navdata_gap_s = 0.1;
  // Axis weights (world axes) of the pairs. tum_ardrone weighs xy 0.05 (its pairs come from the
  // up/down manoeuvre); here any motion counts, the bottom-camera odometry is trusted a third of the
  // ultrasound.
  double scale_weight_xy = 1.0;
  double scale_weight_z = 3.0;
  // An object's world pose is refined over its first sightings while SLAM localizes the drone.
  int object_placement_frames = 30;
  // The face's world pose follows the teacher with this time constant.
  Seconds face_memory_s = 1.0;
};

// Reads the "estimation" section; every key optional, defaults above, delays in ms at this edge.
EstimatorConfig read_estimation_config(const ConfigReader& node);
// The same keys read over `base`: a key absent keeps base's value. For a drone's own estimation
// section (the tello section's "estimation", docs/tello.md) over the estimation section.
EstimatorConfig read_estimation_config(const ConfigReader& node, const EstimatorConfig& base);

}  // namespace labo::estimation
