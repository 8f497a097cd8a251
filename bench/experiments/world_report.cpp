#include "bench/experiments/world_report.hpp"

#include <numbers>

namespace labo::bench {

using lab::TeacherSpec;

using sim::Disturbance;
using sim::PlacementDraw;
using sim::PlantDeviation;
using sim::QuadrotorParams;
using sim::SensorBiases;
using sim::SimWorld;
using sim::deviated_airframe;
using sim::deviated_rotors;
using sim::to_string;


namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

template <typename V>
nlohmann::json array_of(const V& v, double scale = 1.0) {
  nlohmann::json a = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(v.size()); ++i) a.push_back(scale * v[i]);
  return a;
}

nlohmann::json drone_json(const QuadrotorParams& p) {
  const PlantDeviation& d = p.deviation;
  return {{"mass_kg", deviated_airframe(p).mass_kg},
          {"mass_factor", d.mass_factor},
          {"rotor_drag_factor", d.rotor_drag_factor},
          {"air_drag_factor", d.air_drag_factor},
          {"motor_lag_s", deviated_rotors(p).lag_s},
          {"attitude_lag_factor", d.attitude_lag_factor},
          {"yaw_lag_factor", d.yaw_lag_factor},
          {"vertical_lag_factor", d.vertical_lag_factor},
          {"rotor_efficiency", array_of(d.rotor_efficiency)},
          {"battery_start_percent", p.battery.start_percent},
          {"battery_internal_resistance_ohm", p.battery.internal_resistance_ohm}};
}

nlohmann::json biases_json(const SensorBiases& b) {
  return {{"attitude_deg", array_of(b.attitude_rad, kRadToDeg)},
          {"velocity_scale", b.velocity_scale},
          {"velocity_mps", array_of(b.velocity_mps)},
          {"ultrasound_scale", b.ultrasound_scale},
          {"ultrasound_offset_m", b.ultrasound_offset_m},
          {"gyro_radps", array_of(b.gyro_radps)},
          {"accel_mps2", array_of(b.accel_mps2)}};
}

nlohmann::json camera_json(const CameraIntrinsics& k, const Eigen::Vector3d& tilt_rad) {
  return {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy},
          {"distortion", {k.k1, k.k2, k.p1, k.p2, k.k3}},
          {"mounting_tilt_deg", tilt_rad.norm() * kRadToDeg},
          {"mounting_rotation_deg", array_of(tilt_rad, kRadToDeg)}};
}

nlohmann::json event_json(const Disturbance& e) {
  nlohmann::json j = {{"kind", to_string(e.kind)}, {"t_s", e.t_s}, {"duration_s", e.duration_s}};
  switch (e.kind) {
    case Disturbance::Kind::Impulse:
      j["dv_mps"] = array_of(e.dv_heading_mps);
      j["yaw_deg"] = e.dyaw_rad * kRadToDeg;
      break;
    case Disturbance::Kind::Gust: j["wind_mps"] = array_of(e.wind_world_mps); break;
    case Disturbance::Kind::Lighting: j["gain"] = e.exposure_gain; break;
    case Disturbance::Kind::Flicker:
      j["amplitude"] = e.flicker_amplitude;
      j["frequency_hz"] = e.flicker_hz;
      break;
    default: break;
  }
  return j;
}

// The teacher's walk up to `until_s`: the waypoints the path's time reaches by then (and the one
// walked to), each with the pause there; a teacher who gave way to the drone is behind that time.
nlohmann::json teacher_json(const TeacherSpec& t, Seconds until_s) {
  nlohmann::json waypoints = nlohmann::json::array();
  Seconds at = 0;
  for (std::size_t i = 0; i < t.waypoints.size() && at <= until_s; ++i) {
    const double pause = t.pauses_s.empty() ? t.pause_s : t.pauses_s[i];
    waypoints.push_back({{"x", t.waypoints[i].x()}, {"y", t.waypoints[i].y()}, {"pause_s", pause}});
    if (i + 1 < t.waypoints.size()) at += pause + (t.waypoints[i + 1] - t.waypoints[i]).norm() / t.speed_mps;
  }
  return {{"path", t.loop ? "the lab file's, looped" : "drawn"},
          {"speed_mps", t.speed_mps},
          {"head_yaw_amplitude_deg", t.head.yaw_amplitude_deg},
          {"head_yaw_period_s", t.head.yaw_period_s},
          {"give_way", {{"keep_clear_m", t.give_way.keep_clear_m}, {"side_step_m", t.give_way.side_step_m}}},
          {"waypoints", waypoints}};
}

}  // namespace

nlohmann::json world_json(const SimWorld& w, Seconds until_s) {
  nlohmann::json placements = nlohmann::json::array();
  for (const PlacementDraw& p : w.placements)
    placements.push_back({{"id", p.id}, {"offset_m", array_of(p.offset_m)}, {"offset_norm_m", p.offset_m.norm()},
                          {"rotation_deg", array_of(p.rotation_rad, kRadToDeg)}, {"angle_deg", p.rotation_rad.norm() * kRadToDeg}});
  nlohmann::json events = nlohmann::json::array();
  for (const Disturbance& e : w.settings.disturbances)
    if (e.t_s <= until_s) events.push_back(event_json(e));
  nlohmann::json nominal = nlohmann::json::array();
  for (sim::WorldFactor f : sim::kWorldFactors)
    if (w.nominal_factors.contains(f)) nominal.push_back(to_string(f));
  return {{"mode", to_string(w.mode)},
          {"seed", w.seed},
          {"nominal_factors", nominal},
          {"drone", drone_json(w.settings.dynamics)},
          {"sensor_biases", biases_json(w.settings.biases)},
          {"placements", placements},
          {"cameras", {{"front", camera_json(w.cameras.front, w.front_tilt_rad)},
                       {"bottom", camera_json(w.cameras.bottom, w.bottom_tilt_rad)}}},
          {"link", {{"video_delay_s", w.link.video_delay_s}, {"navdata_delay_s", w.link.navdata_delay_s}}},
          {"events", events},
          {"teacher", teacher_json(w.lab.teacher, until_s)}};
}

}  // namespace labo::bench
