#include "drone/sim/sim_config.hpp"

#include <array>
#include <numbers>
#include <string>

#include "core/config_reader.hpp"
#include "drone/ardrone2/ardrone_link.hpp"

namespace labo::sim {

using ardrone2::ArdroneLinkSettings;
using ardrone2::read_ardrone_link_settings;


namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

Eigen::Vector3d read_vector(const ConfigReader& r, std::string_view key, double limit) {
  const auto v = r.numbers(key, 3, Range::closed(-limit, limit));
  return {v[0], v[1], v[2]};
}

// Keys of the closed-loop model the simulated drone was before it became a rigid body, with the key
// that now sets what each one set.
void refuse_closed_loop_keys(const ConfigReader& r) {
  constexpr std::array<std::array<const char*, 2>, 4> kMoved{{{"attitude_rate_per_s", "attitude_loop_per_s"},
                                                              {"yaw_response_per_s", "yaw_rate_loop_per_s"},
                                                              {"vertical_response_per_s", "vz_reference_per_s"},
                                                              {"drag_per_s", "rotor_drag_per_s"}}};
  for (const auto& [old_key, new_key] : kMoved) {
    if (r.has(old_key))
      r.fail(old_key, std::string("no longer a sim key: the simulated drone is a rigid body under its firmware's loops "
                                  "(docs/sim.md); the nearest key is ") + new_key);
  }
}

void read_dynamics(const ConfigReader& r, QuadrotorParams& p) {
  refuse_closed_loop_keys(r);
  p.tilt_max_rad = r.number_or("tilt_max_deg", p.tilt_max_rad / kDegToRad, Range::closed(1, 30)) * kDegToRad;
  p.yaw_rate_max_radps = r.number_or("yaw_rate_max_deg_s", p.yaw_rate_max_radps / kDegToRad, Range::closed(10, 360)) * kDegToRad;
  p.vz_max_mps = r.number_or("vz_max_mps", p.vz_max_mps, Range::closed(0.1, 2.0));
  p.takeoff_height_m = r.number_or("takeoff_height_m", p.takeoff_height_m, Range::closed(0.3, 2.5));
  p.altitude_max_m = r.number_or("altitude_max_m", p.altitude_max_m, Range::closed(0.5, 100));
  p.altitude_min_m = r.number_or("altitude_min_m", p.altitude_min_m, Range::closed(0.05, 1.0));
  p.command_timeout_s = r.number_or("command_timeout_s", p.command_timeout_s, Range::closed(0.1, 10));
  p.airframe.mass_kg = r.number_or("mass_kg", p.airframe.mass_kg, Range::closed(0.2, 2.0));
  p.airframe.rotor_drag_per_s = r.number_or("rotor_drag_per_s", p.airframe.rotor_drag_per_s, Range::closed(0, 5));
  p.airframe.air_drag_kg_per_m = r.number_or("air_drag_kg_per_m", p.airframe.air_drag_kg_per_m, Range::closed(0, 1));
  p.rotors.lag_s = r.number_or("motor_lag_s", p.rotors.lag_s, Range::closed(0.005, 0.5));
  p.loops.attitude_loop_per_s = r.number_or("attitude_loop_per_s", p.loops.attitude_loop_per_s, Range::closed(1, 50));
  p.loops.yaw_rate_loop_per_s = r.number_or("yaw_rate_loop_per_s", p.loops.yaw_rate_loop_per_s, Range::closed(1, 100));
  p.loops.vz_reference_per_s = r.number_or("vz_reference_per_s", p.loops.vz_reference_per_s, Range::closed(0.1, 20));
  p.battery.start_percent = r.number_or("battery_start_percent", p.battery.start_percent, Range::closed(1, 100));
  const double minutes = r.number_or("battery_flight_minutes", 100.0 / p.battery.flying_drain_percent_per_s / 60.0,
                                     Range::closed(0.5, 120));
  p.battery.flying_drain_percent_per_s = 100.0 / (minutes * 60.0);
  p.battery.internal_resistance_ohm =
      r.number_or("battery_internal_resistance_ohm", p.battery.internal_resistance_ohm, Range::closed(0, 1));
  if (p.altitude_min_m >= p.altitude_max_m) r.fail("altitude_min_m", "must be below altitude_max_m");
  if (p.takeoff_height_m < p.altitude_min_m || p.takeoff_height_m > p.altitude_max_m) {
    r.fail("takeoff_height_m", "must lie within [altitude_min_m, altitude_max_m]");
  }
  r.finish();
}

void read_sensors(const ConfigReader& r, SensorNoise& n) {
  n.attitude_noise_rad = r.number_or("attitude_noise_deg", n.attitude_noise_rad / kDegToRad, Range::closed(0, 5)) * kDegToRad;
  n.attitude_offset_rad = r.number_or("attitude_offset_deg", n.attitude_offset_rad / kDegToRad, Range::closed(0, 10)) * kDegToRad;
  n.yaw_drift_radps = r.number_or("yaw_drift_deg_per_min", n.yaw_drift_radps / kDegToRad * 60.0, Range::closed(0, 60)) * kDegToRad / 60.0;
  n.velocity_noise_mps = r.number_or("velocity_noise_mps", n.velocity_noise_mps, Range::closed(0, 1));
  n.velocity_min_altitude_m = r.number_or("velocity_min_altitude_m", n.velocity_min_altitude_m, Range::closed(0, 2));
  n.ultrasound_rate_hz = r.number_or("ultrasound_rate_hz", n.ultrasound_rate_hz, Range::closed(1, 200));
  n.ultrasound_noise_m = r.number_or("ultrasound_noise_m", n.ultrasound_noise_m, Range::closed(0, 0.5));
  n.ultrasound_outlier_probability =
      r.number_or("ultrasound_outlier_probability", n.ultrasound_outlier_probability, Range::closed(0, 1));
  r.finish();
}

void read_link(const ConfigReader& r, SimLinkSettings& l) {
  l.full_navdata = r.boolean_or("full_navdata", l.full_navdata);
  l.navdata_delay_s = r.number_or("navdata_delay_s", l.navdata_delay_s, Range::closed(0, 2));
  l.video_delay_s = r.number_or("video_delay_s", l.video_delay_s, Range::closed(0, 2));
  l.command_delay_s = r.number_or("command_delay_s", l.command_delay_s, Range::closed(0, 2));
  l.jitter_s = r.number_or("jitter_s", l.jitter_s, Range::closed(0, 0.5));
  l.navdata_loss = r.number_or("navdata_loss", l.navdata_loss, Range::closed(0, 1));
  l.video_loss = r.number_or("video_loss", l.video_loss, Range::closed(0, 1));
  l.command_loss = r.number_or("command_loss", l.command_loss, Range::closed(0, 1));
  l.h264 = r.boolean_or("h264", l.h264);
  // The sim link streams at the bit rate the driver configures (the "link" section), as the drone does.
  if (r.has("video_bitrate_kbps"))
    r.fail("video_bitrate_kbps", "no longer a sim key: the simulated drone streams at the driver's link.video_max_bitrate_kbps");
  l.camera_switch_delay_s = r.number_or("camera_switch_delay_s", l.camera_switch_delay_s, Range::closed(0, 10));
  r.finish();
}

Disturbance read_disturbance(const ConfigReader& r) {
  Disturbance d;
  const std::string kind = r.choice("kind", {"impulse", "gust", "video_dropout", "link_outage", "lighting", "flicker"});
  d.t_s = r.number("t_s", Range::non_negative());
  if (kind == "impulse") {
    d.kind = Disturbance::Kind::Impulse;
    d.dv_heading_mps = r.has("dv_mps") ? read_vector(r, "dv_mps", 3.0) : Eigen::Vector3d::Zero();
    d.dyaw_rad = r.number_or("yaw_deg", 0.0, Range::closed(-180, 180)) * kDegToRad;
    if (d.dv_heading_mps.isZero() && d.dyaw_rad == 0) r.fail("dv_mps", "an impulse needs dv_mps or yaw_deg");
  } else {
    d.kind = kind == "gust"            ? Disturbance::Kind::Gust
             : kind == "video_dropout" ? Disturbance::Kind::VideoDropout
             : kind == "lighting"      ? Disturbance::Kind::Lighting
             : kind == "flicker"       ? Disturbance::Kind::Flicker
                                       : Disturbance::Kind::LinkOutage;
    d.duration_s = r.number("duration_s", Range{0.0, 600.0, true});
    if (d.kind == Disturbance::Kind::Gust) d.wind_world_mps = read_vector(r, "wind_mps", 10.0);
    // 0.2-5: from a room going dim to a bright lamp; beyond that the 8-bit frames are mostly clipped.
    if (d.kind == Disturbance::Kind::Lighting) d.exposure_gain = r.number("gain", Range::closed(0.2, 5.0));
    if (d.kind == Disturbance::Kind::Flicker) {
      d.flicker_amplitude = r.number("amplitude", Range::closed(0.0, 0.5));
      d.flicker_hz = r.number("frequency_hz", Range::closed(0.0, 100.0));
    }
  }
  r.finish();
  return d;
}

}  // namespace

SimConfig read_sim_config(const ConfigReader& r) {
  SimConfig c;
  c.lab.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, 0, 2147483647));
  c.link.seed = c.lab.seed;
  c.lab.dynamics.step_s = r.number_or("physics_step_s", c.lab.dynamics.step_s, Range::closed(0.0005, 0.02));
  c.lab.teacher = r.boolean_or("teacher", c.lab.teacher);
  c.world = *parse_world_mode(r.choice_or("world", to_string(c.world), {"nominal", "randomized"}));
  if (r.has("dynamics")) read_dynamics(r.object("dynamics"), c.lab.dynamics);
  if (r.has("sensors")) read_sensors(r.object("sensors"), c.lab.sensors);
  if (r.has("link")) read_link(r.object("link"), c.link);
  if (r.has("disturbances")) {
    for (const ConfigReader& d : r.objects("disturbances")) c.lab.disturbances.push_back(read_disturbance(d));
  }
  r.finish();
  return c;
}

SimConfig read_sim_config_of(const ConfigReader& root) {
  SimConfig c = root.has("sim") ? read_sim_config(root.object("sim")) : SimConfig{};
  const ArdroneLinkSettings driver = root.has("link") ? read_ardrone_link_settings(root.object("link")) : ArdroneLinkSettings{};
  c.link.video_bitrate_kbps = driver.video_max_bitrate_kbps;
  return c;
}

}  // namespace labo::sim
