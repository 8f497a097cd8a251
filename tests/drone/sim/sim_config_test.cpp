// The "sim" configuration section: the shipped values load, every bad value is refused naming the key
// and the expected range, unknown keys are refused.
#include <catch2/catch.hpp>

#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "drone/sim/sim_config.hpp"

using namespace labo;
using namespace labo::sim;
using nlohmann::json;

namespace {

json shipped_sim() {
  std::ifstream in(source_root() / "config" / "default.json");
  return json::parse(in)["sim"];
}

SimConfig read(const json& sim) {
  const json root = {{"sim", sim}};
  const ConfigDocument doc = ConfigDocument::parse(root.dump(), "test.json");
  return read_sim_config(doc.root().object("sim"));
}

std::string error_of(const json& sim) {
  try {
    read(sim);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("sim config: the shipped section loads into the documented defaults", "[sim][config]") {
  const SimConfig c = read(shipped_sim());
  const SimConfig d;
  CHECK(c.lab.seed == 1);
  CHECK(c.lab.dynamics.step_s == d.lab.dynamics.step_s);
  CHECK(c.lab.dynamics.tilt_max_rad == Approx(12 * std::numbers::pi / 180));
  CHECK(c.lab.dynamics.yaw_rate_max_radps == Approx(d.lab.dynamics.yaw_rate_max_radps).epsilon(1e-4));
  CHECK(c.lab.dynamics.loops.vz_reference_per_s == d.lab.dynamics.loops.vz_reference_per_s);
  CHECK(c.lab.dynamics.loops.attitude_loop_per_s == d.lab.dynamics.loops.attitude_loop_per_s);
  CHECK(c.lab.dynamics.loops.yaw_rate_loop_per_s == d.lab.dynamics.loops.yaw_rate_loop_per_s);
  CHECK(c.lab.dynamics.airframe.mass_kg == d.lab.dynamics.airframe.mass_kg);
  CHECK(c.lab.dynamics.airframe.air_drag_kg_per_m == d.lab.dynamics.airframe.air_drag_kg_per_m);
  CHECK(c.lab.dynamics.rotors.lag_s == d.lab.dynamics.rotors.lag_s);
  CHECK(c.lab.dynamics.battery.internal_resistance_ohm == d.lab.dynamics.battery.internal_resistance_ohm);
  CHECK(c.lab.dynamics.battery.flying_drain_percent_per_s == Approx(d.lab.dynamics.battery.flying_drain_percent_per_s).epsilon(0.01));
  CHECK(c.world == WorldMode::Nominal);
  CHECK(c.lab.sensors.yaw_drift_radps == Approx(d.lab.sensors.yaw_drift_radps).epsilon(0.05));
  CHECK(c.lab.sensors.ultrasound_outlier_probability == d.lab.sensors.ultrasound_outlier_probability);
  CHECK(c.link.video_delay_s == d.link.video_delay_s);
  CHECK(c.link.seed == c.lab.seed);
  CHECK(c.lab.teacher);
  CHECK(c.lab.disturbances.empty());
  CHECK(read(json::object()).lab.dynamics.airframe.rotor_drag_per_s == d.lab.dynamics.airframe.rotor_drag_per_s);  // every key optional
  json randomized = shipped_sim();
  randomized["world"] = "randomized";
  CHECK(read(randomized).world == WorldMode::Randomized);
}

TEST_CASE("sim config: disturbances are read with their kinds", "[sim][config]") {
  json sim = shipped_sim();
  sim["disturbances"] = json::array({{{"kind", "impulse"}, {"t_s", 20}, {"dv_mps", {0.5, 0, 0}}},
                                     {{"kind", "impulse"}, {"t_s", 25}, {"yaw_deg", 30}},
                                     {{"kind", "gust"}, {"t_s", 30}, {"duration_s", 3}, {"wind_mps", {0, 1.5, 0}}},
                                     {{"kind", "video_dropout"}, {"t_s", 40}, {"duration_s", 0.5}},
                                     {{"kind", "lighting"}, {"t_s", 50}, {"duration_s", 4}, {"gain", 0.6}},
                                     {{"kind", "flicker"}, {"t_s", 0}, {"duration_s", 60}, {"amplitude", 0.05}, {"frequency_hz", 10}}});
  const SimConfig c = read(sim);
  REQUIRE(c.lab.disturbances.size() == 6);
  CHECK(c.lab.disturbances[0].dv_heading_mps.x() == 0.5);
  CHECK(c.lab.disturbances[1].dyaw_rad == Approx(30 * std::numbers::pi / 180));
  CHECK(c.lab.disturbances[2].kind == Disturbance::Kind::Gust);
  CHECK(c.lab.disturbances[2].wind_world_mps.y() == 1.5);
  CHECK(c.lab.disturbances[3].kind == Disturbance::Kind::VideoDropout);
  CHECK(c.lab.disturbances[4].kind == Disturbance::Kind::Lighting);
  CHECK(c.lab.disturbances[4].exposure_gain == 0.6);
  CHECK(c.lab.disturbances[5].kind == Disturbance::Kind::Flicker);
  CHECK(c.lab.disturbances[5].flicker_amplitude == 0.05);
  CHECK(c.lab.disturbances[5].flicker_hz == 10);
}

TEST_CASE("sim config: out-of-range values are refused naming the key and the expected range", "[sim][config]") {
  struct Case {
    const char* pointer;
    json value;
    const char* key;
    const char* expected;
  };
  const Case cases[] = {
      {"/physics_step_s", 0.1, "sim.physics_step_s", "0.02"},
      {"/seed", -3, "sim.seed", "0"},
      {"/dynamics/tilt_max_deg", 45, "sim.dynamics.tilt_max_deg", "30"},
      {"/dynamics/vz_max_mps", 0, "sim.dynamics.vz_max_mps", "0.1"},
      {"/dynamics/rotor_drag_per_s", "fast", "sim.dynamics.rotor_drag_per_s", "5"},
      {"/dynamics/mass_kg", 3, "sim.dynamics.mass_kg", "2"},
      {"/dynamics/motor_lag_s", 0, "sim.dynamics.motor_lag_s", "0.005"},
      {"/dynamics/battery_internal_resistance_ohm", -1, "sim.dynamics.battery_internal_resistance_ohm", "1"},
      {"/world", "real", "sim.world", "randomized"},
      {"/dynamics/battery_start_percent", 120, "sim.dynamics.battery_start_percent", "100"},
      {"/sensors/ultrasound_outlier_probability", 1.5, "sim.sensors.ultrasound_outlier_probability", "1"},
      {"/sensors/velocity_noise_mps", -0.1, "sim.sensors.velocity_noise_mps", "0"},
      {"/link/video_delay_s", 3, "sim.link.video_delay_s", "2"},
      {"/link/navdata_loss", 2, "sim.link.navdata_loss", "1"},
      {"/teacher", "yes", "sim.teacher", "true or false"},
  };
  for (const Case& c : cases) {
    json sim = shipped_sim();
    sim[json::json_pointer(c.pointer)] = c.value;
    const std::string e = error_of(sim);
    INFO(c.pointer << ": " << e);
    CHECK(e.find("test.json") != std::string::npos);
    CHECK(e.find(c.key) != std::string::npos);
    CHECK(e.find(c.expected) != std::string::npos);
  }
}

TEST_CASE("sim config: inconsistent values, bad disturbances and unknown keys are refused", "[sim][config]") {
  json sim = shipped_sim();
  sim["dynamics"]["altitude_min_m"] = 0.9;
  sim["dynamics"]["altitude_max_m"] = 0.8;
  CHECK(error_of(sim).find("sim.dynamics.altitude_min_m: must be below altitude_max_m") != std::string::npos);
  sim = shipped_sim();
  sim["dynamics"]["takeoff_height_m"] = 2.0;
  sim["dynamics"]["altitude_max_m"] = 1.5;
  CHECK(error_of(sim).find("sim.dynamics.takeoff_height_m") != std::string::npos);

  // The simulated drone streams at the driver's bit rate: the old sim key says where it went.
  sim = shipped_sim();
  sim["link"]["video_bitrate_kbps"] = 4000;
  CHECK(error_of(sim).find("sim.link.video_bitrate_kbps: no longer a sim key") != std::string::npos);
  CHECK(error_of(sim).find("link.video_max_bitrate_kbps") != std::string::npos);

  // The closed-loop model's keys say which key of the rigid body's took their place.
  sim = shipped_sim();
  sim["dynamics"]["attitude_rate_per_s"] = 7.0;
  CHECK(error_of(sim).find("sim.dynamics.attitude_rate_per_s: no longer a sim key") != std::string::npos);
  CHECK(error_of(sim).find("attitude_loop_per_s") != std::string::npos);
  sim = shipped_sim();
  sim["dynamics"]["drag_per_s"] = 0.58;
  CHECK(error_of(sim).find("rotor_drag_per_s") != std::string::npos);

  sim = shipped_sim();
  sim["disturbances"] = json::array({{{"kind", "earthquake"}, {"t_s", 1}}});
  CHECK(error_of(sim).find("sim.disturbances[0].kind") != std::string::npos);
  sim["disturbances"] = json::array({{{"kind", "impulse"}, {"t_s", 1}}});
  CHECK(error_of(sim).find("an impulse needs dv_mps or yaw_deg") != std::string::npos);
  sim["disturbances"] = json::array({{{"kind", "gust"}, {"t_s", 1}, {"duration_s", 0}, {"wind_mps", {1, 0, 0}}}});
  CHECK(error_of(sim).find("duration_s") != std::string::npos);
  sim["disturbances"] = json::array({{{"kind", "impulse"}, {"t_s", 1}, {"dv_mps", {1, 0}}}});
  CHECK(error_of(sim).find("dv_mps") != std::string::npos);
  sim["disturbances"] = json::array({{{"kind", "lighting"}, {"t_s", 1}, {"duration_s", 2}}});
  CHECK(error_of(sim).find("sim.disturbances[0].gain") != std::string::npos);
  sim["disturbances"] = json::array({{{"kind", "lighting"}, {"t_s", 1}, {"duration_s", 2}, {"gain", 9}}});
  CHECK(error_of(sim).find("gain") != std::string::npos);

  sim = shipped_sim();
  sim["link"]["delay_s"] = 0.1;
  CHECK(error_of(sim).find("delay_s") != std::string::npos);
  sim = shipped_sim();
  sim["gravity"] = 9.81;
  CHECK(error_of(sim).find("gravity") != std::string::npos);
}
