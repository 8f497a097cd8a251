#include "bench/face/bench_faces_command.hpp"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "bench/face/face_gallery_bench.hpp"
#include "core/source_tree.hpp"
#include "localization/face/face_commands.hpp"

namespace labo::bench {

namespace {

// The paper's LM tracking row of Table 1 (UPNA head pose database): tx, ty, tz mm, roll, yaw, pitch deg.
constexpr double kPaperLm[6] = {11.51, 7.23, 13.38, 0.56, 2.28, 1.45};
// The benchmark's targets for the pooled figures, same order; no face may be worse than twice them.
constexpr double kTarget[6] = {10, 10, 15, 3, 3, 3};
constexpr double kTargetFrameMs = 5;

std::array<double, 6> values(const FaceErrors& e) {
  return {e.tx_mm, e.ty_mm, e.tz_mm, e.roll_deg, e.yaw_deg, e.pitch_deg};
}

nlohmann::json to_json(const FaceErrors& e) {
  return {{"frames", e.frames}, {"tx_mm", e.tx_mm},     {"ty_mm", e.ty_mm},       {"tz_mm", e.tz_mm},
          {"roll_deg", e.roll_deg}, {"yaw_deg", e.yaw_deg}, {"pitch_deg", e.pitch_deg}};
}

// The columns where a face's figure is worse than twice the pooled one (same statistic).
std::string beyond_twice_pooled(const FaceErrors& face, const FaceErrors& pooled) {
  static constexpr const char* kNames[6] = {"tx", "ty", "tz", "roll", "yaw", "pitch"};
  const auto f = values(face), p = values(pooled);
  std::string out;
  for (std::size_t k = 0; k < 6; ++k) {
    if (f[k] <= 2 * p[k]) continue;
    if (!out.empty()) out += ' ';
    out += kNames[k];
  }
  return out;
}

nlohmann::json to_json(const FaceGalleryReport& r, const FaceGalleryOptions& o) {
  nlohmann::json j;
  j["sequences_per_face"] = o.bench.sequences;
  j["lab_sequences_per_face"] = o.bench.lab_sequences;
  j["frames_per_sequence"] = o.bench.frames;
  j["seed"] = o.bench.seed;
  j["faces_measured"] = r.faces_measured;
  j["pooled"] = {{"mean", to_json(r.pooled_mean)}, {"median", to_json(r.pooled_median)}};
  j["frame_ms_median"] = r.frame_ms_median;
  j["paper_lm"] = {{"tx_mm", kPaperLm[0]}, {"ty_mm", kPaperLm[1]}, {"tz_mm", kPaperLm[2]},
                   {"roll_deg", kPaperLm[3]}, {"yaw_deg", kPaperLm[4]}, {"pitch_deg", kPaperLm[5]}};
  for (const auto& p : r.people) {
    nlohmann::json f = {{"name", p.name}, {"held_out", p.held_out}, {"portrait_interocular_px", p.portrait_interocular_px}};
    if (!p.refused.empty()) {
      f["refused"] = p.refused;
    } else {
      f["mean"] = to_json(p.mean);
      f["median"] = to_json(p.median);
      f["detection_rate"] = p.detection_rate;
      f["main_lost_reason"] = p.main_lost_reason;
      f["registration"] = {{"fit_rms_px", p.report.shape_fit_rms_px},
                           {"shape_param_error_rms", p.report.shape_param_error_rms},
                           {"depth_error_mm", p.report.depth_error_mm}};
      f["frame_ms_median"] = p.report.frame_ms_median;
      f["beyond_twice_pooled_mean"] = beyond_twice_pooled(p.mean, r.pooled_mean);
      f["beyond_twice_pooled_median"] = beyond_twice_pooled(p.median, r.pooled_median);
    }
    j["faces"].push_back(f);
  }
  return j;
}

void print_row(const char* name, const FaceErrors& e, const std::string& tail) {
  std::printf("%-12s %6d %7.2f %7.2f %7.2f %6.2f %6.2f %6.2f  %s\n", name, e.frames, e.tx_mm, e.ty_mm, e.tz_mm,
              e.roll_deg, e.yaw_deg, e.pitch_deg, tail.c_str());
}

void print_table(const FaceGalleryReport& r) {
  std::printf("LM tracking per face, mean absolute errors (UPNA's Table 1 statistic); tx ty tz mm, roll yaw pitch deg\n");
  std::printf("%-12s %6s %7s %7s %7s %6s %6s %6s  %s\n", "face", "frames", "tx", "ty", "tz", "roll", "yaw", "pitch",
              "posed, registration shape error, depth error, main loss, beyond 2x pooled");
  for (const auto& p : r.people) {
    const std::string name = p.name + (p.held_out ? "*" : "");
    if (!p.refused.empty()) {
      std::printf("%-12s refused: %s\n", name.c_str(), p.refused.c_str());
      continue;
    }
    char tail[256];
    std::snprintf(tail, sizeof tail, "%.0f %%, %.3f, %.2f mm, %s, %s", 100 * p.detection_rate,
                  p.report.shape_param_error_rms, p.report.depth_error_mm,
                  p.main_lost_reason.empty() ? "-" : p.main_lost_reason.c_str(),
                  beyond_twice_pooled(p.mean, r.pooled_mean).c_str());
    print_row(name.c_str(), p.mean, tail);
  }
  print_row("pooled mean", r.pooled_mean, "");
  print_row("pooled med.", r.pooled_median, "(median of the per-frame absolute errors)");
  std::printf("%-12s %6s %7.2f %7.2f %7.2f %6.2f %6.2f %6.2f\n", "paper (UPNA)", "", kPaperLm[0], kPaperLm[1],
              kPaperLm[2], kPaperLm[3], kPaperLm[4], kPaperLm[5]);
  std::printf("%-12s %6s %7.2f %7.2f %7.2f %6.2f %6.2f %6.2f\n", "target", "", kTarget[0], kTarget[1], kTarget[2],
              kTarget[3], kTarget[4], kTarget[5]);
  std::printf("* held out of tuning. %d faces measured; whole-pipeline CPU time per frame, median %.2f ms (target <= %.0f)\n",
              r.faces_measured, r.frame_ms_median, kTargetFrameMs);
}

}  // namespace

const CommandSpec& faces_bench_command_spec() {
  static const CommandSpec spec{
      "bench faces",
      "",
      "Table 1 per face and pooled: the face benchmark once per face of the gallery (assets/astronaut.png and every "
      "face the detector finds in assets/solvay_1927.png), each registered from its own frontal frames.",
      {{"--config", "FILE", "configuration file (default: config/default.json)"},
       {"--astronaut", "PNG", "the astronaut's photograph (default: assets/astronaut.png; \"\" leaves it out)"},
       {"--group-photo", "PNG", "group photograph the other faces are cut from (default: assets/solvay_1927.png)"},
       {"--faces", "N", "measure at most N faces, in gallery order (default: all)"},
       {"--face", "NAME", "measure that face alone (e.g. solvay_07)"},
       {"--tuning-faces", "", "leave out the faces held out of tuning (every third: solvay_03, _06, ...)"},
       {"--sequences", "N", "head sequences per face, guided and free alternating (default 2)"},
       {"--lab-sequences", "N", "sequences per face drawn by the simulated lab's renderer (default 0)"},
       {"--frames", "N", "frames per sequence (default 100)"},
       {"--seed", "N", "random seed (default 1)"},
       {"--no-lossy-video", "", "skip the H.264 round trip"},
       {"--crops", "DIR", "write each face's crop there (PNG)"},
       {"--json", "", "print the report as JSON"}},
      0,
      0};
  return spec;
}

int run_faces_bench_command(const ParsedArgs& args) {
  const FaceSetup setup = load_face_setup(args);
  FaceGalleryOptions o;
  o.astronaut = args.value_or("--astronaut", (labo::source_root() / "assets" / "astronaut.png").string());
  o.group_photo = args.value_or("--group-photo", (labo::source_root() / "assets" / "solvay_1927.png").string());
  o.max_faces = args.integer_or("--faces", 1000, 1, 1000);
  o.only_face = args.value_or("--face", "");
  o.tuning_faces_only = args.flag("--tuning-faces");
  o.crops_dir = args.value_or("--crops", "");
  FaceBenchOptions& b = o.bench;
  b.sequences = args.integer_or("--sequences", 2, 1, 1000);
  b.lab_sequences = args.integer_or("--lab-sequences", 0, 0, 1000);
  b.frames = args.integer_or("--frames", 100, 3, 100000);
  b.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  b.lossy_video = !args.flag("--no-lossy-video");
  b.lab = (labo::source_root() / "config" / "lab.json").string();
  b.cameras = setup.cameras;
  b.interpupillary_distance_m = setup.face.interpupillary_distance_m;
  const bool json = args.flag("--json");
  const auto report = run_face_gallery_bench(setup.face, setup.camera, o, [&](const std::string& line) {
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
