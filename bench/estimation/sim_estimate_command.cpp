#include "bench/estimation/sim_estimate_command.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "drone/sim/sim_setup.hpp"
#include "bench/estimation/estimation_experiment.hpp"
#include "bench/estimation/lab_plant.hpp"
#include "bench/estimation/model_fit.hpp"
#include "bench/estimation/real_vision_pipeline.hpp"
#include "bench/estimation/surrogate_plant.hpp"
#include "bench/estimation/truth_vision_pipeline.hpp"
#include "localization/face/teacher_head.hpp"

namespace labo::bench {

using sim::SimDroneLink;
using sim::SimInputs;
using sim::SimulatedLab;
using sim::load_sim_inputs;


namespace {
nlohmann::json impulse_json(const ImpulseResult& r) {
  return {{"push_mps", r.push_mps},
          {"peak_displacement_m", r.peak_displacement_m},
          {"returned_within_0_1_m", r.returned},
          {"return_time_s", r.returned ? nlohmann::json(r.return_time_s) : nlohmann::json(nullptr)},
          {"final_estimate_error_m", r.final_estimate_error_m}};
}

nlohmann::json tracking_json(const TrackingErrors& e) {
  return {{"position_rmse_m", e.position_rmse_m}, {"yaw_rmse_deg", e.yaw_rmse_deg}, {"control_rmse_m", e.control_rmse_m}};
}

nlohmann::json scale_windows_json(const std::vector<ScaleWindow>& windows) {
  nlohmann::json out = nlohmann::json::array();
  for (const ScaleWindow& w : windows) out.push_back({w.from_s, w.true_m_per_unit, w.estimated_m_per_unit});
  return out;
}

nlohmann::json bare_floor_json(const BareFloorCrossing& b) {
  return {{"final_error_m", b.final_error_m}, {"max_error_m", b.max_error_m}, {"overshoot_m", b.overshoot_m},
          {"velocity_dropouts", b.dropouts}, {"velocity_dropout_packets", b.dropout_packets},
          {"crash", b.crash}};
}

nlohmann::json run_json(const EstimationResults& r, unsigned seed) {
  return {{"seed", seed},
          {"scale", {{"error_percent", r.scale_error_percent},
                     {"estimated", r.scale_estimated},
                     {"estimated_m_per_unit", r.scale_estimated_m_per_unit},
                     {"true_m_per_unit", r.scale_true_m_per_unit},
                     {"accuracy", r.scale_accuracy},
                     {"pairs", r.scale_pairs},
                     {"outliers_at_arrival", r.scale_outliers},
                     {"scale_changes", r.scale_changes},
                     {"hover_true_m_per_unit", r.scale_true_hover_m_per_unit},
                     {"hover_error_percent", r.scale_error_hover_percent},
                     {"by_window_from_true_estimated", scale_windows_json(r.scale_windows)}}},
          {"hover_slam", tracking_json(r.hover_slam)},
          {"servo_instrument", tracking_json(r.servo)},
          {"dead_reckoning", {{"drift_m_per_s", r.dead_reckoning_drift_m_per_s},
                              {"yaw_drift_deg_per_s", r.dead_reckoning_yaw_drift_deg_per_s}}},
          {"bare_floor_crossing", {{"dropout_detected", bare_floor_json(r.bare_floor)},
                                   {"fusing_every_velocity", bare_floor_json(r.bare_floor_fusing_every_velocity)}}},
          {"z_impulse", {{"servo_instrument", impulse_json(r.impulse_servo)},
                         {"dead_reckoning", impulse_json(r.impulse_dead_reckoning)},
                         {"dead_reckoning_paper_gamma_rule", impulse_json(r.impulse_paper_rule)}}},
          {"delay_compensation", {{"controller_input_error_with_m", r.controller_input_error_compensated_m},
                                  {"controller_input_error_without_m", r.controller_input_error_uncompensated_m},
                                  {"control_rmse_with_m", r.control_rmse_compensated_m},
                                  {"control_rmse_without_m", r.control_rmse_uncompensated_m},
                                  {"gain_percent", 100.0 * (1.0 - r.control_rmse_compensated_m /
                                                                      std::max(1e-9, r.control_rmse_uncompensated_m))}}},
          {"delay_compensation_measured", {{"control_delay_s", r.control_delay_measured_s},
                                           {"controller_input_error_m", r.controller_input_error_measured_delay_m},
                                           {"control_rmse_m", r.control_rmse_measured_delay_m}}},
          {"command_round_trip", {{"measured_s", r.round_trip_measured_s},
                                  {"windows", r.round_trip_windows},
                                  {"true_s", r.round_trip_true_s},
                                  {"configured_s", r.round_trip_configured_s}}},
          {"rejected_inputs", r.rejected_inputs},
          {"rejections", r.rejections}};
}

nlohmann::json constants_json(const estimation::MotionModelConstants& m) {
  return {{"attitude_rate_hz", m.attitude_rate_hz},
          {"tilt_max_deg", m.tilt_max_rad * 180.0 / M_PI},
          {"yaw_response_hz", m.yaw_response_hz},
          {"yaw_rate_max_deg_s", m.yaw_rate_max_radps * 180.0 / M_PI},
          {"vertical_response_hz", m.vertical_response_hz},
          {"vz_max_mps", m.vz_max_mps},
          {"thrust_accel_mps2", m.thrust_accel_mps2},
          {"drag_per_s", m.drag_per_s}};
}

nlohmann::json model_fit_json(const ModelFitReport& fit) {
  nlohmann::json laws = nlohmann::json::array();
  for (const ModelFitLaw& l : fit.laws) {
    laws.push_back({{"law", l.name}, {"samples", l.samples},
                    {"heldout_residual_rms_before", l.residual_rms_before},
                    {"heldout_residual_rms_after", l.residual_rms_after}});
  }
  return {{"flight_s", fit.flight_s}, {"before", constants_json(fit.before)}, {"fitted", constants_json(fit.fitted)},
          {"laws", laws}};
}

using Field = std::function<double(const EstimationResults&)>;
double mean_of(const std::vector<EstimationResults>& rs, const Field& field) {
  double s = 0;
  for (const auto& r : rs) s += field(r);
  return rs.empty() ? 0.0 : s / static_cast<double>(rs.size());
}
double max_of(const std::vector<EstimationResults>& rs, const Field& field) {
  double m = 0;
  for (const auto& r : rs) m = std::max(m, field(r));
  return m;
}
Field member(double EstimationResults::*f) {
  return [f](const EstimationResults& r) { return r.*f; };
}
}  // namespace

const CommandSpec& sim_estimate_command_spec() {
  static const CommandSpec spec{
      "sim estimate",
      "",
      "State-estimation experiments in lockstep: hover/servo/dead-reckoning RMSE, scale, z impulse, delays.",
      {{"--seed", "S", "first seed (default 1)"},
       {"--runs", "N", "number of seeds S, S+1, ... (default 1)"},
       {"--plant", "lab|surrogate",
        "lab (default): the simulated lab behind SimDroneLink; surrogate: the stand-in quadrotor of eval/"},
       {"--vision", "truth|real",
        "truth (default): visual poses from the ground truth with noise; real (lab only): SLAM and the planar "
        "tracker on the rendered frames"},
       {"--slam-only", "", "run only stage 1 (scale) and the SLAM hover; the other figures stay 0"},
       {"--json", "", "print JSON (the default output; kept for scripts)"},
       {"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--fit-model", "", "refit the motion-model constants on the plant and report the fit (no experiments)"}},
      0,
      0};
  return spec;
}

namespace {
PlantFactory plant_factory(const std::string& plant, const std::filesystem::path& config_path, bool teacher_face) {
  if (plant == "surrogate") {
    return [](const PlantRequest& request) -> std::unique_ptr<EstimationPlant> {
      SurrogatePlantOptions options;
      options.navdata_period = request.navdata_period;
      return std::make_unique<SurrogatePlant>(request.seed, options);
    };
  }
  SimInputs sim = load_sim_inputs(config_path);
  auto inputs = std::make_shared<LabPlantInputs>();
  inputs->lab = std::move(sim.lab);
  inputs->cameras = sim.cameras;
  inputs->sim = sim.sim;
  if (teacher_face) inputs->head = face::load_lab_teacher_head(inputs->lab);
  return [inputs](const PlantRequest& request) -> std::unique_ptr<EstimationPlant> {
    return std::make_unique<LabPlant>(*inputs, request);
  };
}
}  // namespace

int run_sim_estimate_command(const ParsedArgs& args) {
  const unsigned first_seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1'000'000));
  const int runs = args.integer_or("--runs", 1, 1, 1000);
  const std::string plant = args.value_or("--plant", "lab");
  if (plant != "lab" && plant != "surrogate") throw UsageError("--plant must be lab or surrogate (got '" + plant + "')");
  const std::string vision = args.value_or("--vision", "truth");
  if (vision != "truth" && vision != "real") throw UsageError("--vision must be truth or real (got '" + vision + "')");
  if (vision == "real" && plant != "lab") throw UsageError("--vision real needs --plant lab (the surrogate renders no frames)");
  const std::filesystem::path config_path =
      args.value_or("--config", (labo::source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(config_path)) throw UsageError("--config " + config_path.string() + ": no such file");
  const ConfigDocument doc = ConfigDocument::load(config_path);
  const ConfigReader root = doc.root();
  const estimation::EstimatorConfig config =
      root.has("estimation") ? estimation::read_estimation_config(root.object("estimation")) : estimation::EstimatorConfig{};
  const VisionThresholds thresholds = root.has("vision") ? read_vision_thresholds(root.object("vision")) : VisionThresholds{};
  const PlantFactory make_plant = plant_factory(plant, config_path, vision == "real");

  nlohmann::json out;
  out["command"] = "sim estimate";
  out["plant"] = plant;
  out["plant_note"] =
      plant == "lab" ? "the simulated lab (drone/sim SimulatedLab: firmware dynamics, sensor model, teacher) behind "
                       "SimDroneLink (the link's delays, jitter and rates; the driver's 30 ms AT loop)"
                     : "SurrogatePlant: a stand-in quadrotor with its own physics and AR.Drone-like sensor flaws";
  if (args.flag("--fit-model")) {
    const auto fit_plant = make_plant(PlantRequest{first_seed + 5000, 1.0 / 200.0, false});
    out["model_fit"] = model_fit_json(fit_motion_model(*fit_plant, config.model));
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  const PipelineKind pipelines =
      vision == "real" ? real_vision_pipelines(config_path)
                       : PipelineKind{"truth", false,
                                      [thresholds](const estimation::EstimatorConfig& c, const EstimationPlant& p, unsigned seed)
                                          -> std::unique_ptr<EstimationPipeline> {
                                        return std::make_unique<TruthVisionPipeline>(c, thresholds, p, seed);
                                      }};

  const ExperimentPhases phases = args.flag("--slam-only") ? ExperimentPhases::SlamOnly : ExperimentPhases::All;
  out["phases"] = phases == ExperimentPhases::SlamOnly ? "stage 1 and the SLAM hover only" : "all";
  std::vector<EstimationResults> results;
  nlohmann::json per_run = nlohmann::json::array();
  for (int i = 0; i < runs; ++i) {
    const unsigned seed = first_seed + static_cast<unsigned>(i);
    results.push_back(run_estimation_experiments(make_plant, pipelines, seed, config, phases));
    per_run.push_back(run_json(results.back(), seed));
  }
  int scale_ok = 0, impulse_ok = 0, impulse_dr_ok = 0, paper_ok = 0;
  for (const auto& r : results) {
    scale_ok += r.scale_error_percent <= 3.0 ? 1 : 0;
    impulse_ok += (r.impulse_servo.returned && r.impulse_servo.return_time_s <= 5.0) ? 1 : 0;
    impulse_dr_ok += (r.impulse_dead_reckoning.returned && r.impulse_dead_reckoning.return_time_s <= 5.0) ? 1 : 0;
    paper_ok += (r.impulse_paper_rule.returned && r.impulse_paper_rule.return_time_s <= 5.0) ? 1 : 0;
  }
  const double n = static_cast<double>(results.size());
  out["vision_input"] = results.front().vision_input;
  out["runs"] = per_run;
  out["summary"] = {
      {"seeds", runs},
      {"scale_within_3_percent_fraction", scale_ok / n},
      {"scale_error_percent_mean", mean_of(results, member(&EstimationResults::scale_error_percent))},
      {"scale_error_percent_max", max_of(results, member(&EstimationResults::scale_error_percent))},
      {"hover_slam_position_rmse_within_5_cm_fraction",
       mean_of(results, [](const EstimationResults& r) { return r.hover_slam.position_rmse_m <= 0.05 ? 1.0 : 0.0; })},
      {"hover_slam_position_rmse_m_mean", mean_of(results, [](const EstimationResults& r) { return r.hover_slam.position_rmse_m; })},
      {"hover_slam_position_rmse_m_max", max_of(results, [](const EstimationResults& r) { return r.hover_slam.position_rmse_m; })},
      {"hover_slam_yaw_rmse_deg_mean", mean_of(results, [](const EstimationResults& r) { return r.hover_slam.yaw_rmse_deg; })},
      {"servo_position_rmse_m_mean", mean_of(results, [](const EstimationResults& r) { return r.servo.position_rmse_m; })},
      {"servo_position_rmse_m_max", max_of(results, [](const EstimationResults& r) { return r.servo.position_rmse_m; })},
      {"servo_yaw_rmse_deg_mean", mean_of(results, [](const EstimationResults& r) { return r.servo.yaw_rmse_deg; })},
      {"dead_reckoning_drift_m_per_s_mean", mean_of(results, member(&EstimationResults::dead_reckoning_drift_m_per_s))},
      {"dead_reckoning_drift_m_per_s_max", max_of(results, member(&EstimationResults::dead_reckoning_drift_m_per_s))},
      {"dead_reckoning_yaw_drift_deg_per_s_mean", mean_of(results, member(&EstimationResults::dead_reckoning_yaw_drift_deg_per_s))},
      {"bare_floor_final_error_m_mean", mean_of(results, [](const EstimationResults& r) { return r.bare_floor.final_error_m; })},
      {"bare_floor_final_error_m_max", max_of(results, [](const EstimationResults& r) { return r.bare_floor.final_error_m; })},
      {"bare_floor_fusing_every_velocity_final_error_m_mean",
       mean_of(results, [](const EstimationResults& r) { return r.bare_floor_fusing_every_velocity.final_error_m; })},
      {"z_impulse_servo_returned_within_5_s_fraction", impulse_ok / n},
      {"z_impulse_peak_displacement_m_mean",
       mean_of(results, [](const EstimationResults& r) { return r.impulse_servo.peak_displacement_m; })},
      {"z_impulse_servo_return_time_s_max",
       max_of(results, [](const EstimationResults& r) { return r.impulse_servo.return_time_s; })},
      {"z_impulse_dead_reckoning_return_time_s_max",
       max_of(results, [](const EstimationResults& r) { return r.impulse_dead_reckoning.return_time_s; })},
      {"z_impulse_dead_reckoning_returned_within_5_s_fraction", impulse_dr_ok / n},
      {"z_impulse_paper_gamma_rule_returned_within_5_s_fraction", paper_ok / n},
      {"controller_input_error_with_delay_compensation_m_mean",
       mean_of(results, member(&EstimationResults::controller_input_error_compensated_m))},
      {"controller_input_error_without_delay_compensation_m_mean",
       mean_of(results, member(&EstimationResults::controller_input_error_uncompensated_m))},
      {"control_rmse_with_delay_compensation_m_mean", mean_of(results, member(&EstimationResults::control_rmse_compensated_m))},
      {"control_rmse_without_delay_compensation_m_mean", mean_of(results, member(&EstimationResults::control_rmse_uncompensated_m))},
      {"controller_input_error_with_measured_delay_m_mean",
       mean_of(results, member(&EstimationResults::controller_input_error_measured_delay_m))},
      {"control_rmse_with_measured_delay_m_mean", mean_of(results, member(&EstimationResults::control_rmse_measured_delay_m))},
      {"command_round_trip_measured_s_mean", mean_of(results, member(&EstimationResults::round_trip_measured_s))},
      {"command_round_trip_measured_s_max", max_of(results, member(&EstimationResults::round_trip_measured_s))},
      {"command_round_trip_true_s", results.front().round_trip_true_s},
      {"command_round_trip_configured_s", results.front().round_trip_configured_s}};
  out["targets"] = {{"scale_within_3_percent_fraction", ">= 0.95"},
                    {"hover_slam_position_rmse_m", "<= 0.05"},
                    {"z_impulse_returned_within_5_s_fraction", "1.0 (within 0.1 m of the set point)"}};
  std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace labo::bench
