#include "bench/slam/slam_bench_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/camera_config.hpp"
#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "bench/slam/lab_flight.hpp"
#include "bench/slam/lens_error.hpp"
#include "bench/slam/slam_benchmark.hpp"
#include "bench/slam/synthetic_room.hpp"
#include "localization/slam/slam_config.hpp"

namespace labo::bench {

using lab::LabDescription;
using lab::load_lab_description;

namespace {

nlohmann::json to_json(const FlightReport& r) {
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
  j["new_point_clearance_skips"] = r.clearance_skips;
  j["loop_correction_ms_max"] = r.loop_ms_max;
  j["loop_search_ms_median"] = r.loop_search_ms_median;
  j["loop_search_ms_p95"] = r.loop_search_ms_p95;
  if (r.relocalization_s) j["relocalization_s"] = *r.relocalization_s;
  if (r.attempted > 0) {
    const auto percent = [&](long long n) { return std::round(1000.0 * static_cast<double>(n) / static_cast<double>(r.attempted)) / 10; };
    j["points_attempted_percent"] = {{"found", percent(r.found)},
                                     {"no_feature_near", percent(r.misses.no_feature)},
                                     {"descriptor_too_far", percent(r.misses.too_far)},
                                     {"ambiguous", percent(r.misses.ambiguous)},
                                     {"feature_taken", percent(r.misses.taken)},
                                     {"pose_outlier", percent(r.misses.pose_outliers)}};
  }
  if (r.lost_at_distance_m || r.closest_tracked_distance_m > 0) {
    j["lost_at_distance_m"] = r.lost_at_distance_m ? nlohmann::json(*r.lost_at_distance_m) : nlohmann::json(nullptr);
    j["closest_tracked_distance_m"] = r.closest_tracked_distance_m;
  }
  return j;
}

// The simulated lab of a config file (its "lab" and "cameras").
struct LabFlightSetup {
  LabFlightSetup(const ConfigDocument& doc, const std::filesystem::path& config_file, bool noise)
      : lab(load_lab_description(config_file.parent_path() / doc.root().string_or("lab", "lab.json"))),
        cameras(read_cameras_config(doc.root().object("cameras"))),
        camera(cameras.front),
        frames(lab, cameras, noise) {}
  LabDescription lab;
  CamerasConfig cameras;
  PinholeCamera camera;
  SimulatedLabFrames frames;
};

}  // namespace

const CommandSpec& bench_slam_command_spec() {
  static const CommandSpec spec{
      "bench slam",
      "",
      "Monocular SLAM on ground-truth flights: ATE (Sim(3)), RPE, scale drift, timings, relocalization",
      {{"--json", "", "print JSON instead of a table"},
       {"--flight", "NAME", "tour, yaw, approach (synthetic room), lab-inspect, lab-sweep (simulated lab) or all (default all)"},
       {"--lab-fps", "N", "frames per second of the lab flights (default 30; the inspect test runs 15)"},
       {"--sweep-rate", "R", "lab-sweep: the yaw rate in rad/s (default 0.4, face-follow's face_search_yaw_rate)"},
       {"--sweeps", "N", "lab-sweep: full turns (default 2: the second shows whether the first one's map is found again)"},
       {"--sweep-orbit-m", "R", "lab-sweep: the camera looks out from a circle of this radius (default 0: turns in place)"},
       {"--lens-error", "F,C,K1,K2", "lab flights: SLAM's lens model off the rendering's: focal length by the fraction F, principal "
                                     "point by C px, k1 and k2 by K1, K2 (the randomized world draws within 0.03, 5, 0.03, 0.03)"},
       {"--tour-seconds", "S", "duration of the tour flight (default 120)"},
       {"--threaded", "", "mapping in its own thread (default: synchronous, deterministic)"},
       {"--config", "FILE", "the configuration (default config/default.json, as flights): its \"slam\" section (mapping key ignored: see --threaded); "
                            "lab-inspect also takes the lab and the cameras from it"},
       {"--no-noise", "", "render without sensor noise (isolates systematic errors)"},
       {"--noise-seed", "N", "another realization of the synthetic room's sensor noise (default 0; single runs of the tour move by "
                             "several cm with any perturbation: compare variants over a few seeds)"},
       {"--no-distortion", "", "a lens without distortion, for the renderer and the SLAM alike"},
       {"--attitude-noise-deg", "X", "the IMU roll/pitch noise per frame given to SLAM (default 0.09, drone/sim's)"},
       {"--attitude-offset-deg", "X", "sigma of the IMU's constant roll/pitch offset, drawn per flight from the noise seed "
                                      "(default 0.06: after a flat trim; 0.6 without)"},
       {"--trace", "", "print every frame that is not tracked well, and keyframes, to stderr"},
       {"--tum-dir", "DIR", "write each flight's estimate and ground truth as TUM trajectories (for evo)"}},
      0,
      0};
  return spec;
}

int run_bench_slam_command(const ParsedArgs& args) {
  const std::string which = args.value_or("--flight", "all");
  if (which != "all" && which != "tour" && which != "yaw" && which != "approach" && which != "lab-inspect" && which != "lab-sweep") {
    throw UsageError("--flight must be tour, yaw, approach, lab-inspect, lab-sweep or all, not '" + which + "'");
  }
  const double sweep_rate = args.number_or("--sweep-rate", 0.4, 0.05, 2.0);
  const int sweeps = static_cast<int>(args.integer_or("--sweeps", 2, 1, 10));
  const double sweep_orbit_m = args.number_or("--sweep-orbit-m", 0.0, 0.0, 1.0);
  const std::optional<std::string> lens_error_text = args.value("--lens-error");
  const LensError lens_error = lens_error_text ? parse_lens_error(*lens_error_text) : LensError{};
  const double tour_s = args.number_or("--tour-seconds", 120.0, 10.0, 600.0);
  const double lab_fps = args.number_or("--lab-fps", 30.0, 5.0, 60.0);
  const slam::MappingMode mode = args.flag("--threaded") ? slam::MappingMode::Threaded : slam::MappingMode::Synchronous;
  const std::filesystem::path config_file = args.value_or("--config", (source_root() / "config" / "default.json").string());
  if (const auto dir = args.value("--tum-dir")) {
    // Checked before a flight of several minutes, not after it.
    std::error_code ec;
    std::filesystem::create_directories(*dir, ec);
    if (ec) throw UsageError("--tum-dir " + *dir + ": cannot create the folder: " + ec.message());
  }
  const ConfigDocument doc = ConfigDocument::load(config_file);
  slam::SlamSettings settings;
  if (doc.root().has("slam")) settings = slam::read_slam_settings(doc.root().object("slam"));
  settings.mapping_mode = mode;
  const PinholeCamera camera = args.flag("--no-distortion") ? PinholeCamera::ardrone2_front().without_distortion()
                                                             : PinholeCamera::ardrone2_front();
  SyntheticRoomSpec room_spec;
  if (args.flag("--no-noise")) room_spec.noise_sigma = 0;
  // Each frame's noise is seeded by its index; another noise seed offsets every frame's seed.
  const auto noise_seed = static_cast<unsigned>(args.integer_or("--noise-seed", 0, 0, 1000000));
  const SyntheticRoom room(camera, room_spec);
  ImuAttitudeModel imu;
  imu.noise_rad = args.number_or("--attitude-noise-deg", 0.09, 0.0, 5.0) * M_PI / 180.0;
  imu.offset_rad = args.number_or("--attitude-offset-deg", 0.06, 0.0, 10.0) * M_PI / 180.0;
  imu.seed = noise_seed * 7919u + 17u;
  const FlightRenderer in_room = [&room, noise_seed](const Flight& flight, std::size_t i) {
    return room.render(flight.frames[i].T_world_cam, static_cast<unsigned>(i) + noise_seed * 1000003u);
  };
  std::vector<std::pair<Flight, FlightRenderer>> flights;
  if (which == "all" || which == "tour") flights.emplace_back(tour_flight(tour_s), in_room);
  if (which == "all" || which == "yaw") flights.emplace_back(yaw_flight(), in_room);
  if (which == "all" || which == "approach") flights.emplace_back(approach_flight(room.panel_center()), in_room);
  std::optional<LabFlightSetup> lab;
  const bool lab_inspect = which == "all" || which == "lab-inspect", lab_sweep = which == "all" || which == "lab-sweep";
  if (lab_inspect || lab_sweep) {
    if (args.flag("--no-distortion")) throw UsageError("--no-distortion applies to the synthetic room's flights only");
    lab.emplace(doc, config_file, !args.flag("--no-noise"));
  } else if (lens_error_text) {
    throw UsageError("--lens-error applies to the simulated lab's flights only");
  }
  const FlightRenderer in_lab = [&lab](const Flight& flight, std::size_t i) { return lab->frames.render(flight, i); };
  if (lab_inspect) {
    if (lab->lab.instruments.empty()) throw UsageError(config_file.string() + ": the lab has no instrument to approach");
    flights.emplace_back(lab_inspect_flight(lab->lab, lab->lab.instruments.front(), lab_fps), in_lab);
  }
  if (lab_sweep) flights.emplace_back(lab_sweep_flight(lab->lab, sweep_rate, sweeps, sweep_orbit_m, lab_fps), in_lab);
  nlohmann::json out;
  out["scene"] = "tour, yaw, approach: synthetic room 8x6x3 m, procedural textures, AR.Drone 2.0 front camera with "
                 "distortion, 30 fps; lab-inspect, lab-sweep: the simulated lab (drone/sim LabRenderer: blur, noise)";
  out["noise_sigma"] = room_spec.noise_sigma;
  out["noise_seed"] = noise_seed;
  out["lens_distortion"] = camera.has_distortion();
  out["lab_lens_error"] = {{"focal_fraction", lens_error.focal_fraction}, {"principal_px", lens_error.principal_px},
                           {"k1", lens_error.k1}, {"k2", lens_error.k2}};
  out["mapping_mode"] = mode == slam::MappingMode::Threaded ? "threaded" : "synchronous";
  out["imu_attitude"] = {{"noise_deg", imu.noise_rad * 180.0 / M_PI}, {"offset_sigma_deg", imu.offset_rad * 180.0 / M_PI},
                         {"used_by_slam", settings.gravity_sigma_deg > 0}, {"gravity_sigma_deg", settings.gravity_sigma_deg},
                         {"gravity_in_tracking", settings.gravity_in_tracking}};
  out["targets"] = {{"tracking_ms_median", 10.0}, {"ate_rmse_cm", 3.0}, {"relocalization_s", 1.0}};
  for (const auto& [flight, render] : flights) {
    const PinholeCamera flight_camera = flight.name.starts_with("lab-") ? with_lens_error(lab->camera, lens_error) : camera;
    const FlightReport r = run_flight(render, flight, flight_camera, settings, args.flag("--trace") ? &std::cerr : nullptr, imu);
    if (const auto dir = args.value("--tum-dir")) {
      write_tum_trajectory(*dir + "/" + r.name + "_estimate.tum", r.trajectory, false);
      write_tum_trajectory(*dir + "/" + r.name + "_truth.tum", r.trajectory, true);
      write_tum_trajectory(*dir + "/" + r.name + "_keyframes.tum", r.keyframe_trajectory, false);
      write_tum_trajectory(*dir + "/" + r.name + "_keyframes_truth.tum", r.keyframe_trajectory, true);
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

}  // namespace labo::bench
