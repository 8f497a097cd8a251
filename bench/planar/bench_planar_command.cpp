#include "bench/planar/bench_planar_command.hpp"

#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "core/config_reader.hpp"
#include "bench/planar/perturbation_bench.hpp"
#include "localization/planar/planar_commands.hpp"
#include "bench/planar/sequence_bench.hpp"

namespace labo::bench {

namespace {

nlohmann::json to_json(const TrackerSweepStats& s) {
  return {{"convergence_percent", 100.0 * s.convergence_rate},
          {"final_corner_rms_px_mean", s.mean_converged_rms_px},
          {"final_corner_rms_px_median", s.median_converged_rms_px},
          {"median_ms_per_call", s.median_ms},
          {"mean_ms_per_call", s.mean_ms},
          {"mean_iterations", s.mean_iterations}};
}

nlohmann::json sweep_json(const std::vector<PerturbationRow>& rows, const PerturbationSettings& settings) {
  nlohmann::json j;
  j["protocol"] = {{"template_px", settings.template_side_px},
                   {"scene_px", {settings.scene_width_px, settings.scene_height_px}},
                   {"trials_per_sigma", settings.trials},
                   {"converged_when", "tracker reports success and corner RMS <= 1 px"},
                   {"pixel_noise_grey_levels", settings.pixel_noise}};
  for (const auto& r : rows) {
    j["rows"].push_back({{"sigma_px", r.sigma_px}, {"ecc", to_json(r.ecc)}, {"ic", to_json(r.ic)}});
  }
  return j;
}

void print_sweep(const std::vector<PerturbationRow>& rows) {
  std::printf("corner-perturbation sweep (template 200 px, 640x480 scene)\n");
  std::printf("%6s | %9s %9s %9s %9s | %9s %9s %9s %9s\n", "sigma", "ECC conv%", "mean rms", "med rms", "ms",
              "IC conv%", "mean rms", "med rms", "ms");
  for (const auto& r : rows) {
    std::printf("%6.1f | %9.1f %9.3f %9.3f %9.2f | %9.1f %9.3f %9.3f %9.2f\n", r.sigma_px, 100 * r.ecc.convergence_rate,
                r.ecc.mean_converged_rms_px, r.ecc.median_converged_rms_px, r.ecc.median_ms, 100 * r.ic.convergence_rate,
                r.ic.mean_converged_rms_px, r.ic.median_converged_rms_px, r.ic.median_ms);
  }
}

nlohmann::json to_json(const RangeBinStats& b) {
  return {{"tracker", b.tracker},
          {"range_m", {b.min_m, b.max_m}},
          {"poses", b.poses},
          {"error_percent_of_range", {{"median", b.median_error_percent}, {"p95", b.p95_error_percent}}},
          {"error_deg", {{"median", b.median_error_deg}, {"p95", b.p95_error_deg}}},
          {"filtered_error_deg", {{"median", b.median_filtered_error_deg}, {"p95", b.p95_filtered_error_deg}}},
          {"rotation_sigma_deg_median", b.median_rotation_sigma_deg},
          {"rotation_error_within_2sigma_percent", b.rotation_within_2sigma_percent}};
}

nlohmann::json to_json(const std::vector<RangeBinStats>& bins) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& b : bins) j.push_back(to_json(b));
  return j;
}

void print_bin(const char* label, const RangeBinStats& b) {
  std::printf("%s%.1f-%.1f m %-4s poses %5d  error %% median %.2f p95 %.2f  deg median %.2f p95 %.2f  sigma deg %.2f "
              "within 2 sigma %.0f %%  filtered deg median %.2f p95 %.2f\n",
              label, b.min_m, b.max_m, b.tracker.c_str(), b.poses, b.median_error_percent, b.p95_error_percent,
              b.median_error_deg, b.p95_error_deg, b.median_rotation_sigma_deg, b.rotation_within_2sigma_percent,
              b.median_filtered_error_deg, b.p95_filtered_error_deg);
}

nlohmann::json sequences_json(const SequenceBenchResult& r) {
  nlohmann::json j;
  j["renderer"] = r.renderer;
  for (const auto& s : r.sequences) {
    j["sequences"].push_back({{"sequence", s.sequence},
                              {"tracker", s.tracker},
                              {"frames", s.frames},
                              {"frames_in_view", s.frames_in_view},
                              {"frames_with_pose", s.frames_with_pose},
                              {"frames_in_view_without_pose", s.frames_in_view_without_pose},
                              {"range_m", {s.min_range_m, s.max_range_m}},
                              {"detections", s.detections},
                              {"losses", s.losses},
                              {"recoveries", s.recoveries},
                              {"max_recovery_frames", s.max_recovery_frames},
                              {"gross_errors", s.gross_errors},
                              {"loss_reasons", s.loss_reasons},
                              {"error_mm", {{"median", s.median_error_mm}, {"p95", s.p95_error_mm}}},
                              {"error_percent_of_range", {{"median", s.median_error_percent}, {"p95", s.p95_error_percent}}},
                              {"error_deg", {{"median", s.median_error_deg}, {"p95", s.p95_error_deg}}},
                              {"filtered_error_deg", {{"median", s.median_filtered_error_deg}, {"p95", s.p95_filtered_error_deg}}},
                              {"refined_poses", s.refined_poses},
                              {"mean_refinement_iterations", s.mean_refinement_iterations},
                              {"rotation_sigma_deg_median", s.median_rotation_sigma_deg},
                              {"rotation_error_within_2sigma_percent", s.rotation_within_2sigma_percent},
                              {"frame_ms", {{"median_all", s.median_frame_ms},
                                            {"median_tracking", s.median_tracking_ms},
                                            {"median_tracking_cpu", s.median_tracking_cpu_ms},
                                            {"p95_tracking", s.p95_tracking_ms},
                                            {"mean_detection", s.mean_detection_ms}}},
                              {"range_bins", to_json(s.range_bins)}});
  }
  j["range_bins"] = to_json(r.range_bins);
  j["h264_seeds"] = {{"seeds", r.h264_seeds}, {"pooled_range_bins", to_json(r.h264_seed_bins)}};
  return j;
}

void print_sequences(const SequenceBenchResult& r) {
  std::printf("\nsequences (%s)\n", r.renderer.c_str());
  std::printf("%-36s %-4s %5s %5s %5s %4s %4s %4s %5s | %7s %6s %6s %6s %6s %5s | %6s %6s %6s\n", "sequence", "trk",
              "frm", "view", "pose", "det", "loss", "rec", "gross", "med mm", "med %", "p95 %", "med deg", "p95 deg",
              "in2s%", "trk ms", "cpu ms", "det ms");
  for (const auto& s : r.sequences) {
    std::printf("%-36s %-4s %5d %5d %5d %4d %4d %4d %5d | %7.1f %6.2f %6.2f %6.2f %6.2f %5.0f | %6.2f %6.2f %6.1f\n",
                s.sequence.c_str(), s.tracker.c_str(), s.frames, s.frames_in_view, s.frames_with_pose, s.detections,
                s.losses, s.max_recovery_frames, s.gross_errors, s.median_error_mm, s.median_error_percent,
                s.p95_error_percent, s.median_error_deg, s.p95_error_deg, s.rotation_within_2sigma_percent,
                s.median_tracking_ms, s.median_tracking_cpu_ms, s.mean_detection_ms);
    if (!s.loss_reasons.empty()) {
      std::printf("    losses:");
      for (const auto& [reason, n] : s.loss_reasons) std::printf(" %s %d", reason.c_str(), n);
      std::printf("\n");
    }
  }
  for (const auto& b : r.range_bins) print_bin("range ", b);
  if (r.h264_seeds > 1) {
    std::printf("\nH.264 approach, %d noise seeds\n", r.h264_seeds);
    for (const auto& s : r.sequences) {
      if (s.sequence.rfind(h264_sequence_name(0), 0) != 0) continue;
      std::printf("%s\n", s.sequence.c_str());
      for (const auto& b : s.range_bins) print_bin("  ", b);
    }
    for (const auto& b : r.h264_seed_bins) print_bin("pooled over seeds ", b);
  }
}

// One row per frame and tracker: enough to see whether an error is a bias (one axis, one sign,
// growing with range) or noise.
void write_frames_csv(std::ofstream& out, const std::string& path, const std::vector<FrameRecord>& frames) {
  out << "sequence,tracker,frame,range_m,in_view,state,has_pose,refined,ex_m,ey_m,ez_m,"
         "rx_deg,ry_deg,rz_deg,rotation_sigma_deg,cpu_ms,filtered_rx_deg,filtered_ry_deg,filtered_rz_deg,"
         "panel_rx_deg,panel_ry_deg,panel_rz_deg\n";
  for (const auto& f : frames) {
    out << f.sequence << ',' << f.tracker << ',' << f.frame << ',' << f.range_m << ',' << f.in_view << ',' << f.state
        << ',' << f.has_pose << ',' << f.refined << ',' << f.position_error_m.x() << ',' << f.position_error_m.y() << ','
        << f.position_error_m.z() << ',' << f.rotation_error_deg.x() << ',' << f.rotation_error_deg.y() << ','
        << f.rotation_error_deg.z() << ',' << f.rotation_sigma_deg << ',' << f.cpu_ms << ','
        << f.filtered_rotation_error_deg.x() << ',' << f.filtered_rotation_error_deg.y() << ','
        << f.filtered_rotation_error_deg.z() << ',' << f.panel_rotation_error_deg.x() << ','
        << f.panel_rotation_error_deg.y() << ',' << f.panel_rotation_error_deg.z() << '\n';
  }
  out.flush();
  if (!out) throw std::runtime_error("--frames-csv: writing '" + path + "' failed");
}

}  // namespace

const CommandSpec& bench_planar_command_spec() {
  static const CommandSpec spec{
      "bench planar",
      "",
      "planar tracking benchmark: corner-perturbation sweep (ECC vs LaboDrone's tracker) and simulated sequences",
      {{"--json", "", "print JSON instead of tables"},
       {"--trials", "N", "trials per sigma in the sweep (default 100)"},
       {"--part", "P", "sweep, sequences or all (default all)"},
       {"--sequence", "NAME", "run only the sequences whose name contains NAME"},
       {"--tracker", "T", "sequences with ic, ecc or both (default both)"},
       {"--config", "FILE", "read the \"vision\" and \"planar\" sections of this config (default: built-in values)"},
       {"--noise", "G", "grey-level noise added to the sweep's scenes (default 2)"},
       {"--h264-kbps", "K", "bit rate of the H.264 sequence, 100-20000 (default 4000: what the driver configures; the firmware's default is 1000)"},
       {"--h264-seeds", "N", "run the H.264 sequence with N sensor-noise seeds, 1-64 (default 1), each reported, then pooled"},
       {"--frames-csv", "FILE", "write every sequence frame's errors (camera frame, per axis) to FILE"}},
      0,
      0};
  return spec;
}

int run_bench_planar_command(const ParsedArgs& args) {
  const bool json = args.flag("--json");
  const std::string part = args.value_or("--part", "all");
  if (part != "all" && part != "sweep" && part != "sequences") {
    throw UsageError("--part must be sweep, sequences or all, not '" + part + "'");
  }
  const std::string tracker = args.value_or("--tracker", "both");
  if (tracker != "both" && tracker != "ic" && tracker != "ecc") {
    throw UsageError("--tracker must be ic, ecc or both, not '" + tracker + "'");
  }
  std::vector<planar::TrackerKind> trackers;
  if (tracker != "ecc") trackers.push_back(planar::TrackerKind::InverseCompositional);
  if (tracker != "ic") trackers.push_back(planar::TrackerKind::Ecc);
  PerturbationSettings settings;
  settings.trials = args.integer_or("--trials", settings.trials, 1, 10000);
  settings.pixel_noise = args.number_or("--noise", settings.pixel_noise, 0.0, 50.0);
  const int h264_kbps = args.integer_or("--h264-kbps", kDefaultH264Kbps, 100, 20000);
  const int h264_seeds = args.integer_or("--h264-seeds", 1, 1, kMaxH264Seeds);
  if (h264_seeds > 1 && part == "sweep") {
    throw UsageError("--h264-seeds needs the sequences (--part sequences or all): the sweep has no H.264 sequence");
  }
  const std::string frames_csv = args.value_or("--frames-csv", "");
  if (!frames_csv.empty() && part == "sweep") {
    throw UsageError("--frames-csv needs the sequences (--part sequences or all): the sweep has no frames");
  }
  std::ofstream frames_out;  // opened before the minutes of benchmarking, so a bad path fails at once
  if (!frames_csv.empty()) {
    frames_out.open(frames_csv);
    if (!frames_out) throw UsageError("--frames-csv: cannot write '" + frames_csv + "'");
  }
  const planar::PlanarCommandSettings settings_from_file = planar::read_planar_command_settings(args);
  const planar::PlanarConfig& config = settings_from_file.planar;
  nlohmann::json out;
  if (part != "sequences") {
    const auto rows = run_perturbation_sweep(settings, config);
    if (json) {
      out["perturbation_sweep"] = sweep_json(rows, settings);
    } else {
      print_sweep(rows);
    }
  }
  if (part != "sweep") {
    const SequenceBenchResult r =
        run_sequence_bench(config, settings_from_file.vision, args.value_or("--sequence", ""), trackers, h264_kbps,
                           h264_seeds);
    if (frames_out.is_open()) write_frames_csv(frames_out, frames_csv, r.frames);
    if (json) {
      out["sequences"] = sequences_json(r);
    } else {
      print_sequences(r);
    }
  }
  if (json) std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace labo::bench
