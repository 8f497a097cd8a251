// `labodrone-bench sim face-follow`: find the teacher and follow the face while they walk, measured
// from the truth. The flight software knows nothing of the walk: with --vision real in a randomized
// world the teacher walks a path drawn for the run (drone/sim/teacher_walk.hpp: random legs over the
// free floor, random pauses, 0.3-0.7 m/s), in the nominal world the lab file's path; the model lab's
// teacher walks 2 m back and forth at 0.5 m/s.
//
// Measured from when the face is first followed (+ 5 s to settle) for --walk seconds, every control
// tick: the camera-to-face distance's error from face_distance_m (RMS), the face's offset from the
// image centre as a fraction of the width (RMS, over the ticks the face is in the image), and the
// fraction of ticks the face is in the image. A run passes when all three meet their targets.
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "bench/experiments/experiment_common.hpp"
#include "bench/experiments/seed_runner.hpp"
#include "bench/experiments/sim_commands.hpp"

namespace labo::bench {

namespace {

constexpr double kFindWithinS = 150.0;  // take-off, the scale manoeuvre and the search
constexpr double kSettleS = 5.0;
constexpr double kTargetDistanceRmsM = 0.15;
constexpr double kTargetCentreRms = 0.15;
constexpr double kTargetInView = 0.90;

struct FaceRun {
  nlohmann::json world;  // the simulated lab's world, drawn values (the teacher's walk) included
  bool found = false;
  double found_at_s = -1;
  bool crashed = false;
  int ticks = 0, in_view_ticks = 0, tracked_ticks = 0, head_ticks = 0;  // face posed; head followed without one
  std::vector<double> distance_error;  // every measured tick
  std::vector<double> centre_error;    // the ticks with the face in the image
  double nearest_m = std::numeric_limits<double>::infinity();  // the drone's nearest approach to the face

  double in_view() const { return ticks > 0 ? static_cast<double>(in_view_ticks) / ticks : 0.0; }
  // Empty when the run meets every target, else why not.
  std::string failure() const {
    if (!found) return fmt("face not followed within %.0f s", kFindWithinS) + (crashed ? "; crashed" : "");
    std::string why;
    const auto add = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
    if (crashed) add("crashed");
    if (rms(distance_error) > kTargetDistanceRmsM) add(fmt("distance RMS %.3f m > %.2f", rms(distance_error), kTargetDistanceRmsM));
    if (rms(centre_error) > kTargetCentreRms) add(fmt("centre RMS %.3f > %.2f", rms(centre_error), kTargetCentreRms));
    if (in_view() < kTargetInView) add(fmt("in view %.1f %% < %.0f %%", 100 * in_view(), 100 * kTargetInView));
    return why;
  }
};

// Whether a camera-frame point projects into the image.
bool in_image(const Eigen::Vector3d& p_cam, const CameraIntrinsics& k) {
  if (p_cam.z() < 0.1) return false;
  const double u = k.fx * p_cam.x() / p_cam.z() + k.cx, v = k.fy * p_cam.y() / p_cam.z() + k.cy;
  return u >= 0 && u < k.width && v >= 0 && v < k.height;
}

FaceRun run_face_follow(const control::FlightStackSetup& setup, double walk_s, ExperimentFlight& f) {
  FaceRun r;
  control::MissionRequest req;
  req.kind = control::RequestKind::FindTeacher;
  f.request(req);
  r.found = f.run_until([&] { return f.stack().status().stage == "3 face-follow" || f.crashed(); }, kFindWithinS) && !f.crashed();
  r.crashed = f.crashed();  // in the search too: a crash there is not a face not found
  if (!r.found) return r;
  r.found_at_s = f.now();
  f.run(kSettleS);
  f.start_teacher_walk();
  const double d = setup.control.mission.face_distance_m;
  for (const double end = f.now() + walk_s; f.now() < end;) {
    f.tick();
    r.crashed = r.crashed || f.crashed();
    const std::optional<Eigen::Isometry3d> face = f.true_face();
    if (!face) continue;
    const Eigen::Vector3d p = f.true_T_cam(*face).translation();
    ++r.ticks;
    r.distance_error.push_back(p.norm() - d);
    r.nearest_m = std::min(r.nearest_m, (face->translation() - f.true_pose().translation()).norm());
    const fusion::TargetObservation& seen = f.stack().status().face;
    const bool followed = seen.state == fusion::TrackState::Tracking;
    r.tracked_ticks += followed && !seen.position_only;
    r.head_ticks += followed && seen.position_only;
    if (!in_image(p, f.true_lab().front)) continue;
    ++r.in_view_ticks;
    r.centre_error.push_back(centre_offset_fraction(p, f.true_lab().front));
  }
  return r;
}

nlohmann::json run_json(unsigned seed, const FaceRun& r) {
  const std::string why = r.failure();
  return {{"seed", seed}, {"passed", why.empty()}, {"why", why}, {"face_followed", r.found}, {"face_found_at_s", r.found_at_s},
          {"crashed", r.crashed}, {"measured_s", r.ticks * ExperimentFlight::kControlDt},
          {"distance_error_rms_m", rms(r.distance_error)}, {"centre_error_rms", rms(r.centre_error)},
          {"centre_error_p95", percentile(r.centre_error, 95)}, {"in_view_fraction", r.in_view()},
          {"tracked_fraction", r.ticks > 0 ? static_cast<double>(r.tracked_ticks) / r.ticks : 0.0},
          {"head_only_fraction", r.ticks > 0 ? static_cast<double>(r.head_ticks) / r.ticks : 0.0},
          {"nearest_m", std::isfinite(r.nearest_m) ? r.nearest_m : -1.0}, {"world", r.world}};
}

}  // namespace

const CommandSpec& sim_face_follow_command_spec() {
  static const CommandSpec spec = [] {
    CommandSpec s{"sim face-follow", "",
                  "find the teacher and follow the face while they walk (paper 6.4): distance, centring and time in view",
                  experiment_option_specs()};
    s.options.push_back({"--walk", "S", "seconds measured after the face is followed and settled (default 60)"});
    for (auto& option : real_vision_option_specs()) s.options.push_back(option);
    s.options.push_back(jobs_option_spec());
    return s;
  }();
  return spec;
}

int run_sim_face_follow_command(const ParsedArgs& args) {
  const ExperimentOptions o = read_experiment_options(args);
  const double walk = args.number_or("--walk", 60.0, 1.0, 600.0);
  const Experiment experiment = make_experiment(o, true);
  const control::FlightStackSetup& setup = experiment.setup;
  const std::vector<FaceRun> results = run_seeded_flights<FaceRun>(o.runs, o.jobs, [&](int i) {
    const auto f = make_flight(experiment, o.seed + static_cast<unsigned>(i));
    FaceRun r = run_face_follow(setup, walk, *f);
    r.world = run_world_json(*f);
    write_run_outputs(o, "face_follow", i, *f);
    return r;
  });
  std::vector<double> dist, centre;
  int found = 0, passed = 0, crashed = 0, ticks = 0, in_view = 0, tracked = 0, head = 0;
  nlohmann::json runs = nlohmann::json::array(), failed = nlohmann::json::array();
  for (int i = 0; i < o.runs; ++i) {
    const unsigned seed = o.seed + static_cast<unsigned>(i);
    const FaceRun& r = results[static_cast<std::size_t>(i)];
    found += r.found;
    crashed += r.crashed;
    ticks += r.ticks;
    in_view += r.in_view_ticks;
    tracked += r.tracked_ticks;
    head += r.head_ticks;
    dist.insert(dist.end(), r.distance_error.begin(), r.distance_error.end());
    centre.insert(centre.end(), r.centre_error.begin(), r.centre_error.end());
    runs.push_back(run_json(seed, r));
    if (const std::string why = r.failure(); why.empty()) ++passed;
    else failed.push_back({{"seed", seed}, {"why", why}});
  }
  const double in_view_fraction = ticks > 0 ? static_cast<double>(in_view) / ticks : 0.0;
  nlohmann::json summary = {{"experiment", "sim face-follow"}, {"note", real_vision_note(o)}, {"world", world_name(experiment)},
                            {"seed", o.seed}, {"runs", o.runs}, {"walk_s", walk},
                            {"runs_face_followed", found}, {"runs_passed", passed}, {"runs_crashed", crashed}, {"failed", failed},
                            {"measured_s", ticks * ExperimentFlight::kControlDt},
                            {"distance_error_rms_m", rms(dist)}, {"target_distance_error_rms_m", kTargetDistanceRmsM},
                            {"centre_error_rms", rms(centre)}, {"centre_error_p95", percentile(centre, 95)},
                            {"target_centre_error_rms", kTargetCentreRms},
                            {"in_view_fraction", in_view_fraction}, {"target_in_view_fraction", kTargetInView},
                            {"tracked_fraction", ticks > 0 ? static_cast<double>(tracked) / ticks : 0.0},
                            {"head_only_fraction", ticks > 0 ? static_cast<double>(head) / ticks : 0.0}, {"per_run", runs}};
  std::vector<std::string> lines = {
      real_vision_note(o),
      fmt("face followed in %.0f/%.0f runs; %.0f runs met every target", found, o.runs, passed) + fmt("; %.0f crashed", crashed),
      fmt("over %.1f s measured: distance error RMS %.3f m (target <= %.2f)", ticks * ExperimentFlight::kControlDt, rms(dist),
          kTargetDistanceRmsM),
      fmt("face in the image %.1f %% of the time (target >= %.0f %%), posed %.1f %%", 100 * in_view_fraction, 100 * kTargetInView,
          ticks > 0 ? 100.0 * tracked / ticks : 0.0) +
          fmt(", head followed without the face %.1f %%", ticks > 0 ? 100.0 * head / ticks : 0.0),
      fmt("face-centre offset RMS %.3f, p95 %.3f of the width while in the image (target RMS <= %.2f)", rms(centre),
          percentile(centre, 95), kTargetCentreRms)};
  for (const auto& miss : failed) lines.push_back("  seed " + std::to_string(miss["seed"].get<unsigned>()) + ": " + miss["why"].get<std::string>());
  report(o, "face_follow", summary, lines);
  return 0;
}

}  // namespace labo::bench
