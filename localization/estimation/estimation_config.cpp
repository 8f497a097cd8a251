#include "localization/estimation/estimation_config.hpp"

namespace labo::estimation {

namespace {
void read_model(const ConfigReader& n, MotionModelConstants& m) {
  m.attitude_rate_hz = n.number_or("attitude_rate_hz", m.attitude_rate_hz, Range{0.1, 100.0});
  m.tilt_max_rad = n.number_or("tilt_max_deg", m.tilt_max_rad * 180.0 / 3.14159265358979323846, Range{1.0, 45.0}) *
                   3.14159265358979323846 / 180.0;
  m.yaw_response_hz = n.number_or("yaw_response_hz", m.yaw_response_hz, Range{0.1, 100.0});
  m.yaw_rate_max_radps = n.number_or("yaw_rate_max_deg_s", m.yaw_rate_max_radps * 180.0 / 3.14159265358979323846,
                                     Range{10.0, 720.0}) * 3.14159265358979323846 / 180.0;
  m.vertical_response_hz = n.number_or("vertical_response_hz", m.vertical_response_hz, Range{0.1, 100.0});
  m.vz_max_mps = n.number_or("vz_max_mps", m.vz_max_mps, Range{0.1, 3.0});
  m.thrust_accel_mps2 = n.number_or("thrust_accel_mps2", m.thrust_accel_mps2, Range{1.0, 30.0});
  m.drag_per_s = n.number_or("drag_per_s", m.drag_per_s, Range{0.01, 10.0});
  n.finish();
}

void read_noise(const ConfigReader& n, EstimatorNoise& e) {
  const auto sigma = [&](const char* key, double& v) { v = n.number_or(key, v, Range::positive()); };
  sigma("accel_xy_mps2", e.accel_xy_mps2);
  sigma("accel_z_mps2", e.accel_z_mps2);
  sigma("attitude_radps", e.attitude_radps);
  sigma("yaw_accel_radps2", e.yaw_accel_radps2);
  sigma("attitude_obs_rad", e.attitude_obs_rad);
  sigma("yaw_increment_rad", e.yaw_increment_rad);
  sigma("velocity_mps", e.velocity_mps);
  sigma("velocity_with_vision_mps", e.velocity_with_vision_mps);
  sigma("vertical_velocity_mps", e.vertical_velocity_mps);
  sigma("ultrasound_m", e.ultrasound_m);
  sigma("slam_position_m", e.slam_position_m);
  sigma("slam_yaw_rad", e.slam_yaw_rad);
  sigma("object_position_m", e.object_position_m);
  sigma("object_yaw_rad", e.object_yaw_rad);
  sigma("face_position_m", e.face_position_m);
  sigma("face_yaw_rad", e.face_yaw_rad);
  sigma("survey_position_m", e.survey_position_m);
  sigma("survey_rotation_rad", e.survey_rotation_rad);
  n.finish();
}

void read_reacquisition(const ConfigReader& n, ReacquisitionSettings& r) {
  r.chi2 = n.number_or("chi2", r.chi2, Range::positive());
  r.max_jump_m = n.number_or("max_jump_m", r.max_jump_m, Range::closed(0.05, 10.0));
  r.confirm_frames = n.integer_or("confirm_frames", r.confirm_frames, 1, 1000);
  r.confirm_spread_m = n.number_or("confirm_spread_m", r.confirm_spread_m, Range::closed(0.001, 1.0));
  n.finish();
}

void read_velocity_dropout(const ConfigReader& n, VelocityDropoutSettings& d) {
  d.enabled = n.boolean_or("enabled", d.enabled);
  d.window_s = n.number_or("window_s", d.window_s, Range::closed(0.05, 5.0));
  d.average_s = n.number_or("average_s", d.average_s, Range{0.0, 1.0, true});
  if (d.average_s >= d.window_s) n.fail("average_s", "must be shorter than window_s");
  d.onset_mps = n.number_or("onset_mps", d.onset_mps, Range::positive());
  d.onset_ratio = n.number_or("onset_ratio", d.onset_ratio, Range::closed(0.0, 1.0));
  d.alive_mps = n.number_or("alive_mps", d.alive_mps, Range::positive());
  d.agree_mps = n.number_or("agree_mps", d.agree_mps, Range::positive());
  d.confirm_packets = n.integer_or("confirm_packets", d.confirm_packets, 1, 100);
  d.dropout_accel_noise_mps2 = n.number_or("dropout_accel_noise_mps2", d.dropout_accel_noise_mps2, Range::positive());
  n.finish();
}

void read_drift_bound(const ConfigReader& n, DriftBoundSettings& d) {
  d.velocity_bias_mps = n.number_or("velocity_bias_mps", d.velocity_bias_mps, Range::closed(0.0, 1.0));
  d.velocity_scale = n.number_or("velocity_scale", d.velocity_scale, Range::closed(0.0, 1.0));
  d.dropout_mps = n.number_or("dropout_mps", d.dropout_mps, Range::closed(0.0, 2.0));
  n.finish();
}
}  // namespace

EstimatorConfig read_estimation_config(const ConfigReader& node) { return read_estimation_config(node, EstimatorConfig{}); }

EstimatorConfig read_estimation_config(const ConfigReader& node, const EstimatorConfig& base) {
  EstimatorConfig c = base;
  const auto ms = [&](const char* key, Seconds& v, double max_ms) {
    v = node.number_or(key, v * 1000.0, Range::closed(0.0, max_ms)) / 1000.0;
  };
  ms("video_delay_ms", c.video_delay_s, 1000.0);
  ms("navdata_delay_ms", c.navdata_delay_s, 1000.0);
  ms("control_delay_ms", c.control_delay_s, 1000.0);
  ms("vision_latency_allowance_ms", c.vision_latency_allowance_s, 2000.0);
  c.max_future_s = node.number_or("max_future_s", c.max_future_s, Range{0.0, 60.0, true});
  c.firmware_command_hold_s = node.number_or("firmware_command_hold_s", c.firmware_command_hold_s, Range::closed(0.0, 30.0));
  c.firmware_hover_stop_s = node.number_or("firmware_hover_stop_s", c.firmware_hover_stop_s, Range{0.0, 10.0, true});
  if (node.has("model")) read_model(node.object("model"), c.model);
  if (node.has("noise")) read_noise(node.object("noise"), c.noise);
  c.use_navdata_vz = node.boolean_or("use_navdata_vz", c.use_navdata_vz);
  c.altitude_step_discrimination = node.boolean_or("altitude_step_discrimination", c.altitude_step_discrimination);
  if (node.has("velocity_dropout")) read_velocity_dropout(node.object("velocity_dropout"), c.velocity_dropout);
  if (node.has("drift_bound")) read_drift_bound(node.object("drift_bound"), c.drift_bound);
  c.source_enter_count = node.integer_or("source_enter_count", c.source_enter_count, 1, 100);
  c.source_timeout_s = node.number_or("source_timeout_s", c.source_timeout_s, Range{0.0, 10.0, true});
  c.vision_gate_chi2 = node.number_or("vision_gate_chi2", c.vision_gate_chi2, Range::positive());
  if (node.has("reacquisition")) read_reacquisition(node.object("reacquisition"), c.reacquisition);
  c.inactive_source_noise_factor =
      node.number_or("inactive_source_noise_factor", c.inactive_source_noise_factor, Range{1.0, 100.0});
  c.scale.sigma_map_m = node.number_or("scale_sigma_map_m", c.scale.sigma_map_m, Range::positive());
  c.scale.sigma_metric_m = node.number_or("scale_sigma_metric_m", c.scale.sigma_metric_m, Range::positive());
  c.scale.min_displacement_m = node.number_or("scale_min_displacement_m", c.scale.min_displacement_m, Range::positive());
  c.scale.memory_pairs = node.number_or("scale_memory_pairs", c.scale.memory_pairs, Range{2.0, 1000.0});
  c.scale.outlier_chi2 = node.number_or("scale_outlier_chi2", c.scale.outlier_chi2, Range::positive());
  c.scale_interval_min_s = node.number_or("scale_interval_min_s", c.scale_interval_min_s, Range{0.1, 30.0});
  c.scale_interval_max_s = node.number_or("scale_interval_max_s", c.scale_interval_max_s, Range{0.1, 60.0});
  if (c.scale_interval_max_s <= c.scale_interval_min_s) {
    node.fail("scale_interval_max_s", "must be greater than scale_interval_min_s");
  }
  c.scale_max_navdata_gap_s = node.number_or("scale_max_navdata_gap_s", c.scale_max_navdata_gap_s, Range::closed(0.01, 1.0));
  c.scale_weight_xy = node.number_or("scale_weight_xy", c.scale_weight_xy, Range::non_negative());
  c.scale_weight_z = node.number_or("scale_weight_z", c.scale_weight_z, Range::non_negative());
  c.scale.initial_scale = node.number_or("initial_scale", c.scale.initial_scale, Range::positive());
  c.object_placement_frames = node.integer_or("object_placement_frames", c.object_placement_frames, 0, 10000);
  c.face_memory_s = node.number_or("face_memory_s", c.face_memory_s, Range::positive());
  node.finish();
  return c;
}

}  // namespace labo::estimation
