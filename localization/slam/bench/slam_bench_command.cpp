#include "localization/slam/bench/slam_bench_command.hpp"

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/config_reader.hpp"
#include "localization/slam/bench/slam_benchmark.hpp"
#include "localization/slam/slam_config.hpp"

namespace labo {
namespace {

nlohmann::json to_json(const slam::FlightReport& r) {
  nlohmann::json j;
  j["flight"] = r.name;
  j["frames"] = r.frames;
  j["tracked_frames"] = r.tracked_frames;
  j["good_frames"] = r.good_frames;
  j["lost_frames_after_init"] = r.lost_frames;
  j["initialized_at_s"] = r.initialized_at_s;
  if (r.errors) {
    j["ate_rmse_cm"] = r.errors->ate_rmse_m * 100;
    j["ate_max_cm"] = r.errors->ate_max_m * 100;
    j["rpe_1s_translation_rmse_cm"] = r.errors->rpe_translation_rmse_m * 100;
    j["rpe_1s_rotation_rmse_deg"] = r.errors->rpe_rotation_rmse_deg;
    j["scale_drift_percent"] = r.errors->scale_drift_percent;
    j["rotation_scale_error_percent"] = r.errors->rotation_scale_error_percent;
    j["truth_turned_deg"] = r.errors->truth_turned_deg;
    j["aligned_poses"] = r.errors->poses;
  } else {
    j["ate_rmse_cm"] = nullptr;
  }
  if (r.keyframe_errors) {
    j["keyframe_ate_rmse_cm"] = r.keyframe_errors->ate_rmse_m * 100;
    j["keyframe_scale_drift_percent"] = r.keyframe_errors->scale_drift_percent;
    j["keyframe_rotation_scale_error_percent"] = r.keyframe_errors->rotation_scale_error_percent;
  }
  std::vector<double> windows_cm;
  for (double e : r.ate_by_10s_m) windows_cm.push_back(std::round(e * 1000) / 10);
  j["ate_by_10s_cm"] = windows_cm;
  j["tracking_ms_median"] = r.tracking_ms_median;
  j["tracking_ms_p95"] = r.tracking_ms_p95;
  j["tracking_cpu_ms_median"] = r.tracking_cpu_ms_median;
  j["tracking_cpu_ms_p95"] = r.tracking_cpu_ms_p95;
  j["mapping_ms_per_keyframe_median"] = r.mapping_ms_per_keyframe_median;
  j["mapping_ms_per_keyframe_max"] = r.mapping_ms_per_keyframe_max;
  j["keyframes"] = r.keyframes;
  j["map_points"] = r.map_points;
  j["global_ba_runs"] = r.global_ba_runs;
  j["loops_detected"] = r.loops_detected;
  j["loops_corrected"] = r.loops_corrected;
  j["points_fused"] = r.points_fused;
  j["loop_correction_ms_max"] = r.loop_ms_max;
  j["loop_search_ms_median"] = r.loop_search_ms_median;
  j["loop_search_ms_p95"] = r.loop_search_ms_p95;
  if (r.relocalization_s) j["relocalization_s"] = *r.relocalization_s;
  if (r.name == "approach") {
    j["lost_at_distance_m"] = r.lost_at_distance_m ? nlohmann::json(*r.lost_at_distance_m) : nlohmann::json(nullptr);
    j["closest_tracked_distance_m"] = r.closest_tracked_distance_m;
  }
  return j;
}

}  // namespace

const CommandSpec& bench_slam_command_spec() {
  static const CommandSpec spec{
      "bench slam",
      "",
      "Monocular SLAM on ground-truth flights: ATE (Sim(3)), RPE, scale drift, timings, relocalization",
      {{"--json", "", "print JSON instead of a table"},
       {"--flight", "NAME", "tour, yaw, approach or all (default all)"},
       {"--tour-seconds", "S", "duration of the tour flight (default 120)"},
       {"--threaded", "", "mapping in its own thread (default: synchronous, deterministic)"},
       {"--config", "FILE", "read the \"slam\" section of this config (its mapping key is ignored: see --threaded)"},
       {"--no-noise", "", "render without sensor noise (isolates systematic errors)"},
       {"--no-distortion", "", "a lens without distortion, for the renderer and the SLAM alike"},
       {"--trace", "", "print every frame that is not tracked well, and keyframes, to stderr"},
       {"--tum-dir", "DIR", "write each flight's estimate and ground truth as TUM trajectories (for evo)"}},
      0,
      0};
  return spec;
}

int run_bench_slam_command(const ParsedArgs& args) {
  const std::string which = args.value_or("--flight", "all");
  if (which != "all" && which != "tour" && which != "yaw" && which != "approach") {
    throw UsageError("--flight must be tour, yaw, approach or all, not '" + which + "'");
  }
  const double tour_s = args.number_or("--tour-seconds", 120.0, 10.0, 600.0);
  const slam::MappingMode mode = args.flag("--threaded") ? slam::MappingMode::Threaded : slam::MappingMode::Synchronous;
  slam::SlamSettings settings;
  if (const auto file = args.value("--config")) {
    const ConfigDocument doc = ConfigDocument::load(*file);
    if (doc.root().has("slam")) settings = slam::read_slam_settings(doc.root().object("slam"));
  }
  settings.mapping_mode = mode;
  const PinholeCamera camera = args.flag("--no-distortion") ? PinholeCamera::ardrone2_front().without_distortion()
                                                             : PinholeCamera::ardrone2_front();
  slam::SyntheticRoomSpec room_spec;
  if (args.flag("--no-noise")) room_spec.noise_sigma = 0;
  const slam::SyntheticRoom room(camera, room_spec);
  std::vector<slam::Flight> flights;
  if (which == "all" || which == "tour") flights.push_back(slam::tour_flight(tour_s));
  if (which == "all" || which == "yaw") flights.push_back(slam::yaw_flight());
  if (which == "all" || which == "approach") flights.push_back(slam::approach_flight(room.panel_center()));
  nlohmann::json out;
  out["scene"] = "synthetic room 8x6x3 m, procedural textures, AR.Drone 2.0 front camera with distortion, 30 fps";
  out["noise_sigma"] = room_spec.noise_sigma;
  out["lens_distortion"] = camera.has_distortion();
  out["mapping_mode"] = mode == slam::MappingMode::Threaded ? "threaded" : "synchronous";
  out["targets"] = {{"tracking_ms_median", 10.0}, {"ate_rmse_cm", 3.0}, {"relocalization_s", 1.0}};
  for (const auto& flight : flights) {
    const slam::FlightReport r = slam::run_flight(room, flight, camera, settings, args.flag("--trace") ? &std::cerr : nullptr);
    if (const auto dir = args.value("--tum-dir")) {
      slam::write_tum_trajectory(*dir + "/" + r.name + "_estimate.tum", r.trajectory, false);
      slam::write_tum_trajectory(*dir + "/" + r.name + "_truth.tum", r.trajectory, true);
      slam::write_tum_trajectory(*dir + "/" + r.name + "_keyframes.tum", r.keyframe_trajectory, false);
      slam::write_tum_trajectory(*dir + "/" + r.name + "_keyframes_truth.tum", r.keyframe_trajectory, true);
    }
    const nlohmann::json j = to_json(r);
    out["flights"].push_back(j);
    if (!args.flag("--json")) std::cerr << j.dump() << "\n";
  }
  if (args.flag("--json")) {
    std::cout << out.dump(2) << "\n";
  } else {
    for (const auto& j : out["flights"]) {
      std::cout << j["flight"].get<std::string>() << ": ATE " << j["ate_rmse_cm"] << " cm, tracking median "
                << j["tracking_ms_median"] << " ms (p95 " << j["tracking_ms_p95"] << "; CPU median " << j["tracking_cpu_ms_median"]
                << " ms), tracked " << j["tracked_frames"] << "/"
                << j["frames"] << "\n";
    }
  }
  return 0;
}

}  // namespace labo
