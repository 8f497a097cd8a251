#include "bench/face/bench_face_command.hpp"

#include <iostream>
#include <nlohmann/json.hpp>

#include "bench/face/face_bench.hpp"
#include "core/source_tree.hpp"
#include "localization/face/face_commands.hpp"

namespace labo::bench {

namespace {

struct PaperRow {
  const char* name;
  double tx, ty, tz, roll, yaw, pitch, time;
};
// The paper's Table 1 (UPNA head pose database).
constexpr PaperRow kPaper[] = {{"EPNP", 11.84, 7.11, 12.67, 0.55, 3.74, 2.39, 0.117},
                               {"Ransac P3P", 12.50, 7.79, 18.34, 1.56, 6.52, 6.11, 0.898},
                               {"EPNP + LM", 11.51, 7.23, 13.38, 0.56, 2.28, 1.45, 0.363},
                               {"Ransac P3P + LM", 11.51, 7.23, 13.38, 0.56, 2.28, 1.45, 1.138},
                               {"LM", 11.51, 7.23, 13.38, 0.56, 2.28, 1.45, 0.234}};

nlohmann::json to_json(const FaceBenchReport& r, const FaceBenchOptions& o) {
  nlohmann::json j;
  j["sequences"] = o.sequences;
  j["lab_sequences"] = o.lab_sequences;
  j["frames_per_sequence"] = o.frames;
  j["seed"] = o.seed;
  j["video"] = o.lossy_video ? "h264 " + std::to_string(o.video_bitrate_kbps) + " kbit/s" : "none";
  j["frames_total"] = r.frames_total;
  j["detection_rate"] = r.frames_total ? static_cast<double>(r.frames_tracked) / r.frames_total : 0.0;
  for (std::size_t i = 0; i < r.methods.size(); ++i) {
    const auto& m = r.methods[i];
    j["methods"].push_back({{"method", face::to_string(m.method)}, {"frames", m.frames}, {"failures", m.failures},
                            {"tx_mm", m.tx_mm}, {"ty_mm", m.ty_mm}, {"tz_mm", m.tz_mm}, {"roll_deg", m.roll_deg},
                            {"yaw_deg", m.yaw_deg}, {"pitch_deg", m.pitch_deg}, {"time_ms", m.time_ms},
                            {"absolute", {{"tx_mm", m.abs_tx_mm}, {"ty_mm", m.abs_ty_mm}, {"tz_mm", m.abs_tz_mm}}},
                            {"paper", {{"tx_mm", kPaper[i].tx}, {"ty_mm", kPaper[i].ty}, {"tz_mm", kPaper[i].tz},
                                       {"roll_deg", kPaper[i].roll}, {"yaw_deg", kPaper[i].yaw},
                                       {"pitch_deg", kPaper[i].pitch}, {"time_ms", kPaper[i].time}}}});
  }
  j["frame_ms"] = {{"median", r.frame_ms_median}, {"mean", r.frame_ms_mean}, {"p95", r.frame_ms_p95},
                   {"median_tracking_no_detector", r.tracking_frame_ms_median},
                   {"detect_median", r.detect_ms_median}, {"landmarks_median", r.landmarks_ms_median},
                   {"pose_median", r.pose_ms_median}};
  j["registration"] = {{"frames", r.registration_frames},
                       {"fit_rms_px", r.shape_fit_rms_px},
                       {"shape_param_error_rms", r.shape_param_error_rms},
                       {"turn_views", r.turn_views},
                       {"turn_rms_before_px", r.turn_rms_before_px},
                       {"turn_rms_after_px", r.turn_rms_after_px},
                       {"turn_refused", r.turn_refused},
                       {"depth_error_mm", {{"registered", r.depth_error_mm}, {"after_turn", r.depth_error_turned_mm},
                                           {"registered_untilted", r.depth_error_untilted_mm},
                                           {"after_turn_untilted", r.depth_error_untilted_turned_mm}}}};
  for (const auto& s : r.sequences) {
    j["per_sequence"].push_back({{"name", s.name}, {"renderer", s.renderer}, {"distance_m", s.distance_m}, {"detection_rate", s.detection_rate},
                                 {"lm_yaw_err_deg", s.yaw_err_deg}, {"lm_tz_err_mm", s.tz_err_mm}});
  }
  for (const auto& [renderer, m] : r.lm_by_renderer) {
    j["lm_tracking_by_renderer"][renderer] = {{"frames", m.frames}, {"tx_mm", m.tx_mm}, {"ty_mm", m.ty_mm},
                                              {"tz_mm", m.tz_mm}, {"roll_deg", m.roll_deg}, {"yaw_deg", m.yaw_deg},
                                              {"pitch_deg", m.pitch_deg}};
  }
  for (const auto& [reason, count] : r.lost_reasons) j["lost_reasons"][reason] = count;
  return j;
}

void print_table(const FaceBenchReport& r) {
  std::printf("%-16s %8s %8s %8s %7s %7s %7s %8s   (paper: tx ty tz roll yaw pitch time)\n", "Method", "tx", "ty",
              "tz", "roll", "yaw", "pitch", "time");
  for (std::size_t i = 0; i < r.methods.size(); ++i) {
    const auto& m = r.methods[i];
    const auto& p = kPaper[i];
    std::printf("%-16s %8.2f %8.2f %8.2f %7.2f %7.2f %7.2f %8.3f   (%.2f %.2f %.2f %.2f %.2f %.2f %.3f)\n", p.name,
                m.tx_mm, m.ty_mm, m.tz_mm, m.roll_deg, m.yaw_deg, m.pitch_deg, m.time_ms, p.tx, p.ty, p.tz, p.roll,
                p.yaw, p.pitch, p.time);
  }
  std::printf("tx, ty, tz in mm (motion relative to each sequence's first frame, as UPNA); roll, yaw, pitch in degrees; "
              "time in ms (pose only)\n");
  for (const auto& m : r.methods) {
    std::printf("absolute translation error %-14s tx %.1f ty %.1f tz %.1f mm\n", std::string(face::to_string(m.method)).c_str(),
                m.abs_tx_mm, m.abs_ty_mm, m.abs_tz_mm);
  }
  std::printf("detection rate %.1f %% of %d frames; whole per-frame time median %.2f ms (tracking, no detector: %.2f), "
              "mean %.2f, p95 %.2f; stages median: detect %.2f, landmarks %.2f, pose %.3f\n",
              r.frames_total ? 100.0 * r.frames_tracked / r.frames_total : 0.0, r.frames_total, r.frame_ms_median,
              r.tracking_frame_ms_median, r.frame_ms_mean, r.frame_ms_p95, r.detect_ms_median, r.landmarks_ms_median,
              r.pose_ms_median);
  for (const auto& [renderer, m] : r.lm_by_renderer) {
    std::printf("LM tracking, %s-rendered sequences (%d frames): tx %.2f ty %.2f tz %.2f mm, roll %.2f yaw %.2f pitch %.2f deg\n",
                renderer.c_str(), m.frames, m.tx_mm, m.ty_mm, m.tz_mm, m.roll_deg, m.yaw_deg, m.pitch_deg);
  }
  std::printf("registration (%d frames): fit RMS %.2f px, shape parameter error (RMS over fitted units) %.3f\n",
              r.registration_frames, r.shape_fit_rms_px, r.shape_param_error_rms);
  if (r.turn_views > 0) {
    std::printf("head turn: %d views, landmark fit %.2f -> %.2f px\n", r.turn_views, r.turn_rms_before_px,
                r.turn_rms_after_px);
  }
  if (!r.turn_refused.empty()) std::printf("head turn not used: %s\n", r.turn_refused.c_str());
  std::printf("landmark depth error against the rendered head (evaluation only): %.2f mm RMS registered, %.2f after "
              "the turn; without the tilt part %.2f and %.2f mm\n",
              r.depth_error_mm, r.depth_error_turned_mm, r.depth_error_untilted_mm, r.depth_error_untilted_turned_mm);
  for (const auto& [reason, count] : r.lost_reasons) std::printf("lost: %-60s %d frames\n", reason.c_str(), count);
}

}  // namespace

const CommandSpec& face_bench_command_spec() {
  static const CommandSpec spec{
      "bench face",
      "",
      "Face pose methods (the paper's Table 1) on rendered head-pose sequences with known pose.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--texture", "PNG", "photograph with one face for the head (default: assets/astronaut.png)"},
       {"--sequences", "N", "number of sequences, guided and free alternating (default 10)"},
       {"--frames", "N", "frames per sequence (default 300)"},
       {"--seed", "N", "random seed (default 1)"},
       {"--no-lossy-video", "", "skip the H.264 round trip"},
       {"--bitrate-kbps", "N", "H.264 bit rate (default 1000, the AR.Drone 2.0's)"},
       {"--samples", "DIR", "write a few rendered frames there"},
       {"--lab-sequences", "N", "more sequences drawn by the simulated lab's LabRenderer (default 4; 0 none)"},
       {"--lab", "FILE", "lab description for those (default: config/lab.json)"},
       {"--frames-csv", "FILE", "write per-frame truth and LM-tracking errors there, with FILE.poses.csv (true and estimated poses) and FILE.model.csv (camera, registered and true landmarks) beside it (for analysis)"},
       {"--registration-frames", "N", "register the teacher from N consecutive frames of the still, frontal head, landmarks averaged (default 8)"},
       {"--true-shape", "", "use the rendered head's shape instead of the one registered from the frontal frames"},
       {"--turn-frames", "N", "refine the registered landmarks' depth from N frames of the head turning (default 0: off)"},
       {"--turn-yaw-deg", "DEG", "how far the head turns left and right in those frames (default 25)"},
       {"--turn-pitch-deg", "DEG", "how far it nods up and down (default 15)"},
       {"--sequence", "NAME", "run only the sequence of that name (e.g. free_5_138cm, lab_guided_0_50cm)"},
       {"--json", "", "print the report as JSON"}},
      0,
      0};
  return spec;
}

int run_face_bench_command(const ParsedArgs& args) {
  const FaceSetup setup = load_face_setup(args);
  FaceBenchOptions o;
  o.sequences = args.integer_or("--sequences", 10, 1, 1000);
  o.frames = args.integer_or("--frames", 300, 3, 100000);
  o.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  o.texture = args.value_or("--texture", (labo::source_root() / "assets" / "astronaut.png").string());
  o.lossy_video = !args.flag("--no-lossy-video");
  o.video_bitrate_kbps = args.integer_or("--bitrate-kbps", 1000, 100, 20000);
  o.sample_dir = args.value_or("--samples", "");
  o.true_shape = args.flag("--true-shape");
  o.registration_frames = args.integer_or("--registration-frames", 8, 1, 100);
  o.turn_frames = args.integer_or("--turn-frames", 0, 0, 10000);
  o.turn_yaw_deg = args.number_or("--turn-yaw-deg", 25, 0, 60);
  o.turn_pitch_deg = args.number_or("--turn-pitch-deg", 15, 0, 45);
  o.frames_csv = args.value_or("--frames-csv", "");
  o.only_sequence = args.value_or("--sequence", "");
  o.lab_sequences = args.integer_or("--lab-sequences", 4, 0, 1000);
  o.lab = args.value_or("--lab", (labo::source_root() / "config" / "lab.json").string());
  o.cameras = setup.cameras;
  o.interpupillary_distance_m = setup.face.interpupillary_distance_m;
  const bool json = args.flag("--json");
  const auto report = run_face_bench(setup.face, setup.camera, o, [&](const std::string& line) {
    if (!json) std::cerr << line << "\n";
  });
  if (json) {
    std::cout << to_json(report, o).dump(2) << "\n";
  } else {
    print_table(report);
  }
  return 0;
}

}  // namespace labo::bench
