#include "drone/sim/sim_world.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/frames.hpp"
#include "drone/sim/seeded_draw.hpp"

namespace labo::sim {

using lab::InstrumentSpec;
using lab::LabDescription;


namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// The world's draws: their own stream, apart from the sensors' and the link's (seeded with the same
// number) and the teacher's walk.
constexpr std::uint32_t kWorldStream = 0x776f726cu;

Eigen::Matrix3d rotation_of(const Eigen::Vector3d& rotation_rad) {
  const double angle = rotation_rad.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, rotation_rad / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

void draw_drone(SeededDraw& d, const WorldRanges& r, QuadrotorParams& p) {
  PlantDeviation& dev = p.deviation;
  dev.mass_factor = d.around(1.0, r.mass);
  dev.rotor_drag_factor = d.around(1.0, r.drag);
  dev.air_drag_factor = d.around(1.0, r.drag);
  dev.motor_lag_factor = d.around(1.0, r.inner_loop_lag);
  dev.attitude_lag_factor = d.around(1.0, r.inner_loop_lag);
  dev.yaw_lag_factor = d.around(1.0, r.inner_loop_lag);
  dev.vertical_lag_factor = d.around(1.0, r.inner_loop_lag);
  for (double& e : dev.rotor_efficiency) e = d.around(1.0, r.rotor_thrust);
  p.battery.start_percent = d.in(r.battery_start_percent);
  p.battery.internal_resistance_ohm = d.in(r.battery_resistance_ohm);
}

void draw_biases(SeededDraw& d, const WorldRanges& r, SensorBiases& b) {
  b.attitude_rad = Eigen::Vector2d(d.plus_minus(r.attitude_bias_deg), d.plus_minus(r.attitude_bias_deg)) * kDegToRad;
  b.velocity_scale = d.around(1.0, r.velocity_scale);
  b.velocity_mps = Eigen::Vector2d(d.plus_minus(r.velocity_bias_mps), d.plus_minus(r.velocity_bias_mps));
  b.ultrasound_scale = d.around(1.0, r.ultrasound_scale);
  b.ultrasound_offset_m = d.plus_minus(r.ultrasound_bias_m);
  for (int i = 0; i < 3; ++i) b.gyro_radps[i] = d.plus_minus(r.gyro_bias_radps);
  for (int i = 0; i < 3; ++i) b.accel_mps2[i] = d.plus_minus(r.accel_bias_mps2);
}

PlacementDraw move_object(SeededDraw& d, const WorldRanges& r, InstrumentSpec& object, bool on_floor) {
  PlacementDraw draw{object.id, d.in_ball(r.placement_m, on_floor), Eigen::Vector3d::Zero()};
  draw.rotation_rad = on_floor ? Eigen::Vector3d(0, 0, d.plus_minus(r.placement_deg * kDegToRad))
                               : d.in_ball(r.placement_deg * kDegToRad);
  object.T_world_object.linear() = rotation_of(draw.rotation_rad) * object.T_world_object.linear();
  object.T_world_object.translation() += draw.offset_m;
  return draw;
}

void draw_placements(SeededDraw& d, const WorldRanges& r, SimWorld& w) {
  for (InstrumentSpec& instrument : w.lab.instruments) w.placements.push_back(move_object(d, r, instrument, false));
  // The drone stands on the platform where it really is.
  const Eigen::Isometry3d T_platform_base = w.lab.platform.T_world_object.inverse() * w.lab.T_world_base;
  w.placements.push_back(move_object(d, r, w.lab.platform, true));
  w.lab.T_world_base = w.lab.platform.T_world_object * T_platform_base;
}

void draw_camera(SeededDraw& d, const WorldRanges& r, CameraIntrinsics& k, double k1_range) {
  const double focal = d.around(1.0, r.focal_fraction), aspect = d.around(1.0, r.aspect_fraction);
  k.fx *= focal * aspect;
  k.fy *= focal;
  k.cx += d.plus_minus(r.principal_point_px);
  k.cy += d.plus_minus(r.principal_point_px);
  k.k1 += d.plus_minus(k1_range);
  k.k2 += d.plus_minus(r.k2);
  k.p1 += d.plus_minus(r.tangential);
  k.p2 += d.plus_minus(r.tangential);
}

void draw_cameras(SeededDraw& d, const WorldRanges& r, SimWorld& w) {
  draw_camera(d, r, w.cameras.front, r.k1);
  draw_camera(d, r, w.cameras.bottom, r.bottom_k1);
  w.front_tilt_rad = d.in_ball(r.mounting_tilt_deg * kDegToRad);
  w.bottom_tilt_rad = d.in_ball(r.mounting_tilt_deg * kDegToRad);
  w.mounts.front.linear() = w.mounts.front.linear() * rotation_of(w.front_tilt_rad);
  w.mounts.bottom.linear() = w.mounts.bottom.linear() * rotation_of(w.bottom_tilt_rad);
}

void draw_events(SeededDraw& d, const WorldRanges& r, std::vector<Disturbance>& events) {
  for (double t : d.event_times(r.lighting_interval_s, r.horizon_s)) {
    Disturbance e;
    e.kind = Disturbance::Kind::Lighting;
    e.t_s = t;
    e.exposure_gain = d.in(r.lighting_gain);
    e.duration_s = d.in(r.lighting_duration_s);
    events.push_back(e);
  }
  Disturbance flicker;
  flicker.kind = Disturbance::Kind::Flicker;
  flicker.duration_s = r.horizon_s;
  flicker.flicker_amplitude = d.in(r.flicker_amplitude);
  flicker.flicker_hz = d.in(r.flicker_hz);
  events.push_back(flicker);
  const auto bursts = [&](double mean_s, const WorldInterval& duration, Disturbance::Kind kind) {
    for (double t : d.event_times(mean_s, r.horizon_s)) {
      Disturbance e;
      e.kind = kind;
      e.t_s = t;
      e.duration_s = d.in(duration);
      events.push_back(e);
    }
  };
  bursts(r.link_loss_interval_s, r.link_loss_s, Disturbance::Kind::LinkOutage);
  bursts(r.video_stall_interval_s, r.video_stall_s, Disturbance::Kind::VideoDropout);
}

// Sets the factors of `keep` back to the configuration's values (`nominal`, the world before any draw;
// the events the configuration itself lists are kept).
void restore_nominal(const SimWorld& nominal, const WorldFactorSet& keep, SimWorld& w) {
  using enum WorldFactor;
  if (keep.contains(Drone)) w.settings.dynamics = nominal.settings.dynamics;
  if (keep.contains(Sensors)) w.settings.biases = nominal.settings.biases;
  if (keep.contains(Placements)) {
    w.lab.instruments = nominal.lab.instruments;
    w.lab.platform = nominal.lab.platform;
    w.lab.T_world_base = nominal.lab.T_world_base;
    w.placements.clear();
  }
  if (keep.contains(Lens)) w.cameras = nominal.cameras;
  if (keep.contains(Mounting)) {
    w.mounts = nominal.mounts;
    w.front_tilt_rad = w.bottom_tilt_rad = Eigen::Vector3d::Zero();
  }
  if (keep.contains(Delays)) {
    w.link.video_delay_s = nominal.link.video_delay_s;
    w.link.navdata_delay_s = nominal.link.navdata_delay_s;
  }
  if (keep.contains(Teacher)) w.lab.teacher = nominal.lab.teacher;
  const auto drawn_event_kept = [&](const Disturbance& e) {
    const bool light = e.kind == Disturbance::Kind::Lighting || e.kind == Disturbance::Kind::Flicker;
    const bool link = e.kind == Disturbance::Kind::LinkOutage || e.kind == Disturbance::Kind::VideoDropout;
    return !(light && keep.contains(Lighting)) && !(link && keep.contains(Link));
  };
  auto& events = w.settings.disturbances;
  const auto first_drawn = events.begin() + static_cast<std::ptrdiff_t>(nominal.settings.disturbances.size());
  events.erase(std::remove_if(first_drawn, events.end(), [&](const Disturbance& e) { return !drawn_event_kept(e); }),
               events.end());
}

}  // namespace

std::string to_string(WorldFactor factor) {
  switch (factor) {
    case WorldFactor::Drone: return "drone";
    case WorldFactor::Sensors: return "sensors";
    case WorldFactor::Placements: return "placements";
    case WorldFactor::Lens: return "lens";
    case WorldFactor::Mounting: return "mounting";
    case WorldFactor::Delays: return "delays";
    case WorldFactor::Lighting: return "lighting";
    case WorldFactor::Link: return "link";
    case WorldFactor::Teacher: return "teacher";
  }
  return "?";
}

std::optional<WorldFactor> parse_world_factor(std::string_view text) {
  for (WorldFactor f : kWorldFactors) {
    if (text == to_string(f)) return f;
  }
  return std::nullopt;
}

SimWorld make_sim_world(const LabDescription& lab_file, const CamerasConfig& calibration, const SimConfig& sim,
                        const WorldRanges& ranges) {
  SimWorld w;
  w.mode = sim.world;
  w.seed = sim.lab.seed;
  w.lab = lab_file;
  w.cameras = calibration;
  w.settings = sim.lab;
  w.link = sim.link;
  if (w.mode == WorldMode::Nominal) return w;
  const SimWorld nominal = w;
  SeededDraw d(w.seed, kWorldStream);
  draw_drone(d, ranges, w.settings.dynamics);
  draw_biases(d, ranges, w.settings.biases);
  draw_placements(d, ranges, w);
  draw_cameras(d, ranges, w);
  w.link.video_delay_s = d.in(ranges.video_delay_s);
  w.link.navdata_delay_s = d.in(ranges.navdata_delay_s);
  draw_events(d, ranges, w.settings.disturbances);
  if (ranges.teacher_walk) w.lab.teacher = random_teacher_walk(lab_file, w.seed, *ranges.teacher_walk);
  restore_nominal(nominal, ranges.nominal, w);
  w.nominal_factors = ranges.nominal;
  return w;
}

}  // namespace labo::sim
