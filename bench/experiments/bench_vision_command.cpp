#include "bench/experiments/bench_vision_command.hpp"

#include "control/flight_stack.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/experiments/detector_comparison.hpp"
#include "bench/frame_timing.hpp"
#include "localization/fusion/face_front_end.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/planar_front_end.hpp"
#include "localization/fusion/slam_front_end.hpp"
#include "core/candide3.hpp"
#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "core/frames.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "drone/sim/render_commands.hpp"
#include "localization/face/head_tracker.hpp"
#include "localization/face/teacher_head.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "bench/slam/bench_flights.hpp"
#include "bench/slam/synthetic_room.hpp"

namespace labo::bench {

using lab::default_lab_path;
using lab::load_lab_description;


namespace {

struct Timing {
  std::string name, what;
  FrameTimes times;
  int ok = 0;  // frames with a result (tracking / pose)
};

// Views of a lab target from `distance` m, drifting slowly (as a hovering drone does).
std::vector<cv::Mat> panel_views(const fusion::PlanarTarget& target, const PinholeCamera& camera, double distance, int n) {
  const cv::Mat templ = cv::imread(target.template_path.string(), cv::IMREAD_GRAYSCALE);
  if (templ.empty()) throw std::runtime_error("bench vision: cannot read " + target.template_path.string());
  const PlanarViewRenderer renderer(camera, make_clutter_background(cv::Size(1200, 1200), 5), 0.0025);
  std::vector<cv::Mat> out;
  for (int i = 0; i < n; ++i) {
    const double s = 0.02 * std::sin(0.2 * i);
    out.push_back(renderer.render(templ, target.width_m, target.height_m,
                                  look_at_object(Eigen::Vector3d(0.05 + s, -0.03 + 0.5 * s, -distance + s), Eigen::Vector3d::Zero())));
  }
  return out;
}

Timing planar_timing(const std::string& name, const std::string& what, const fusion::PlanarTarget& target, const PinholeCamera& camera,
                     const control::FlightStackSetup& setup, const fusion::FrontEndSettings& s, double distance, int n, bool detect_every_frame) {
  Timing t{name, what, {}, 0};
  const auto frames = panel_views(target, camera, distance, n + 2);
  fusion::PlanarFrontEnd fe(target, camera, setup.vision, s.planar);
  for (int i = 0; i < 2 && !detect_every_frame; ++i) fe.process(frames[static_cast<std::size_t>(i)], i / 30.0, distance);  // warm up
  for (int i = 2; i < n + 2; ++i) {
    if (detect_every_frame) fe.reset();
    const fusion::TargetObservation* o = nullptr;
    t.times.add(time_call([&] { o = &fe.process(frames[static_cast<std::size_t>(i)], i / 30.0, distance); }));
    t.ok += o->state == fusion::TrackState::Tracking ? 1 : 0;
  }
  return t;
}

Timing slam_timing(const fusion::FrontEndSettings& s, const PinholeCamera& camera, int n) {
  Timing t{"slam_track", "SLAM front-end, synthetic room approach flight, frames after initialization", {}, 0};
  slam::SlamSettings settings = s.slam;
  settings.mapping_mode = slam::MappingMode::Threaded;  // as the server runs it: mapping off the frame path
  fusion::SlamSystemFrontEnd fe(std::make_unique<slam::SlamSystem>(camera, settings));
  const bench::SyntheticRoom room(camera);
  const bench::Flight flight = bench::approach_flight(room.panel_center());
  for (std::size_t i = 0; i < flight.frames.size() && static_cast<int>(t.times.size()) < n; ++i) {
    const cv::Mat img = room.render(flight.frames[i].T_world_cam, static_cast<unsigned>(i));
    const fusion::SlamFrame* f = nullptr;
    const CallTime ms = time_call([&] { f = &fe.process(img, flight.frames[i].t, std::nullopt); });
    if (f->summary.state == fusion::SlamState::Initializing) continue;
    t.times.add(ms);
    t.ok += f->has_pose ? 1 : 0;
  }
  return t;
}

Timing face_timing(const fusion::FrontEndSettings& s, int n) {
  Timing t{"face_track", "face front-end, textured head at 1.0-1.2 m turning slowly", {}, 0};
  const PinholeCamera camera = PinholeCamera::ardrone2_front().without_distortion();
  auto estimator = std::make_unique<face::FacePoseEstimator>(s.face, camera);
  const Candide3Model candide = Candide3Model::load(s.face.model);
  const cv::Mat photo = cv::imread((source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
  if (photo.empty()) throw std::runtime_error("bench vision: assets/astronaut.png missing (run scripts/setup.sh)");
  face::TexturedHead head = face::texture_head_from_photo(*estimator, candide, photo, 0.063);
  face::TexturedHeadRenderer renderer(candide, head, camera);
  fusion::FaceFrontEnd fe(std::move(estimator));
  for (int i = 0; i < n + 3; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = face::head_rotation({0.3 * std::sin(0.05 * i), 0.1 * std::sin(0.07 * i), 0.0});
    T.translation() = Eigen::Vector3d(0.05 * std::sin(0.03 * i), -0.02, 1.1 + 0.1 * std::sin(0.04 * i));
    cv::Mat img(camera.height(), camera.width(), CV_8UC1, cv::Scalar(120));
    renderer.render(T, img);
    const fusion::TargetObservation* o = nullptr;
    const CallTime ms = time_call([&] { o = &fe.process(img, i / 30.0, std::nullopt); });
    if (i < 3) continue;  // first detection
    t.times.add(ms);
    t.ok += o->state == fusion::TrackState::Tracking ? 1 : 0;
  }
  return t;
}

// The lab's front camera's frame of `scene`, grey.
cv::Mat front_gray(sim::LabRenderer& renderer, const sim::SceneState& scene) {
  cv::Mat bgr, out;
  renderer.render(CameraId::Front, scene, bgr);
  cv::cvtColor(bgr, out, cv::COLOR_BGR2GRAY);
  return out;
}

// The head tracker on the lab's teacher turning their back and walking off to the side at 1.1 m,
// rendered as the lab's front camera renders in flight; learnt from the true pose of the first frame
// (a posed face, as FaceFrontEnd teaches it).
Timing head_timing(int n) {
  Timing t{"head_track", "head tracker, the lab's teacher turning their back at 1.1 m and walking on", {}, 0};
  const lab::LabDescription lab = lab::load_lab_description(default_lab_path());
  sim::LabRenderer renderer(lab, ardrone2_cameras(), face::load_lab_teacher_head(lab), 1, sim::LabRenderOptions{});
  const Eigen::Vector2d start = lab.teacher.waypoints.front();
  const Eigen::Vector3d camera_at(start.x() - 1.1, start.y(), lab.teacher.eye_height_m);
  const auto scene = [&](double s) {
    sim::SceneState st;
    const Eigen::Vector2d at = start + Eigen::Vector2d(0.3 * s, 0.5 * s);
    st.teacher_floor_xy = at;
    st.T_world_head = sim::teacher_head_pose(lab, at.x(), at.y(), std::numbers::pi * (1.0 + s));  // facing the drone (-x), turning round
    st.T_world_body = make_pose(camera_at - T_body_cam_front().translation().x() * Eigen::Vector3d::UnitX(), 0.0);
    return st;
  };
  const auto gray = [&](const sim::SceneState& st) { return front_gray(renderer, st); };
  face::HeadTracker tracker(renderer.camera(CameraId::Front));
  const sim::SceneState first = scene(0.0);
  tracker.learn(gray(first), (first.T_world_body * T_body_cam_front()).inverse() * first.T_world_head, 0.0);
  // Rendered ahead: the renderer's cost is not the tracker's. Turned round over the first 90 frames.
  std::vector<cv::Mat> frames;
  for (int i = 1; i <= n; ++i) frames.push_back(gray(scene(std::min(1.0, i / 90.0))));
  for (int i = 1; i <= n; ++i) {
    std::optional<face::HeadObservation> head;
    t.times.add(time_call([&] { head = tracker.follow(frames[static_cast<std::size_t>(i - 1)], i / 30.0); }));
    t.ok += head.has_value() ? 1 : 0;
  }
  return t;
}

// The head tracker after it lost the head: every frame searched for its kept template round where it
// was lost (the teacher gone from the view, so nothing is found and every frame searches until the
// reacquisition time is up). `ok` counts the frames on which no head was made up.
Timing head_reacquire_timing(int n) {
  Timing t{"head_reacquire", "head tracker, the head lost at 1.1 m: searched for round where it was, at 4 sizes", {}, 0};
  const lab::LabDescription lab = lab::load_lab_description(default_lab_path());
  sim::LabRenderer renderer(lab, ardrone2_cameras(), face::load_lab_teacher_head(lab), 1, sim::LabRenderOptions{});
  const Eigen::Vector2d at = lab.teacher.waypoints.front();
  sim::SceneState st;
  st.teacher_floor_xy = at;
  st.T_world_head = sim::teacher_head_pose(lab, at.x(), at.y(), std::numbers::pi);
  st.T_world_body = make_pose(Eigen::Vector3d(at.x() - 1.1, at.y(), lab.teacher.eye_height_m) -
                                  T_body_cam_front().translation().x() * Eigen::Vector3d::UnitX(), 0.0);
  const auto gray = [&](const sim::SceneState& scene) { return front_gray(renderer, scene); };
  face::HeadTracker tracker(renderer.camera(CameraId::Front));
  tracker.learn(gray(st), (st.T_world_body * T_body_cam_front()).inverse() * st.T_world_head, 0.0);
  tracker.follow(gray(st), 1 / 30.0);
  st.teacher_present = false;
  const cv::Mat empty = gray(st);
  Seconds now = 1 / 30.0;
  for (int i = 0; i < 30 && tracker.active(); ++i) tracker.follow(empty, now += 1 / 30.0);
  if (tracker.active()) return t;  // not lost: nothing to time (ok stays 0)
  const int frames = std::min(n, static_cast<int>(tracker.options().reacquire_s * 30.0) - 1);
  for (int i = 0; i < frames; ++i) {
    std::optional<face::HeadObservation> head;
    t.times.add(time_call([&] { head = tracker.follow(empty, now += 1 / 30.0); }));
    t.ok += head.has_value() ? 0 : 1;
  }
  return t;
}

}  // namespace

const CommandSpec& bench_vision_command_spec() {
  static const CommandSpec spec{
      "bench vision",
      "",
      "per-frame cost of the vision front-ends flight control runs (planar detection and tracking, SLAM, face, the head between posed faces), "
      "and the planar detectors compared",
      {{"--frames", "N", "frames per case (default 100; the detection cases and the detector comparison at most 60)"},
       {"--part", "P", "cases, detectors or all (default all)"},
       {"--json", "", "print the figures as JSON"},
       {"--config", "FILE", "configuration for the planar, slam, face and vision sections (default config/default.json)"}},
      0,
      0};
  return spec;
}

namespace {

nlohmann::json times_json(const FrameTimes& t) {
  return {{"median_ms", quantile_of(t.wall_ms, 0.5)}, {"p95_ms", quantile_of(t.wall_ms, 0.95)}, {"max_ms", quantile_of(t.wall_ms, 1.0)},
          {"cpu_median_ms", quantile_of(t.cpu_ms, 0.5)}, {"cpu_p95_ms", quantile_of(t.cpu_ms, 0.95)},
          {"cpu_max_ms", quantile_of(t.cpu_ms, 1.0)}, {"first_ms", t.wall_ms.empty() ? 0.0 : t.wall_ms.front()},
          {"first_cpu_ms", t.cpu_ms.empty() ? 0.0 : t.cpu_ms.front()}};
}

void print_times(const FrameTimes& t) {
  std::printf("%6.1f %6.1f %6.1f | %6.1f %6.1f %6.1f | %6.1f", quantile_of(t.cpu_ms, 0.5), quantile_of(t.cpu_ms, 0.95),
              quantile_of(t.cpu_ms, 1.0), quantile_of(t.wall_ms, 0.5), quantile_of(t.wall_ms, 0.95), quantile_of(t.wall_ms, 1.0),
              t.cpu_ms.empty() ? 0.0 : t.cpu_ms.front());
}

std::vector<Timing> run_cases(const control::FlightStackSetup& setup, const fusion::FrontEndSettings& s, int n) {
  const fusion::PlanarTarget& osc = *setup.lab.find_instrument("oscilloscope");
  const PinholeCamera front = PinholeCamera::ardrone2_front(), bottom = PinholeCamera::ardrone2_bottom();
  const int detections = std::min(n, 60);
  std::vector<Timing> timings;
  timings.push_back(planar_timing("planar_detect_far", "oscilloscope at 2.8 m: template matching + tracker refinement", osc,
                                  front, setup, s, 2.8, detections, true));
  timings.push_back(planar_timing("planar_detect_near", std::string("oscilloscope at 1.2 m: ") + planar::to_string(s.planar.near_detector) +
                                      " + tracker refinement", osc, front, setup, s, 1.2, detections, true));
  timings.push_back(planar_timing("planar_track", "oscilloscope at 0.8 m (the standoff): frame-to-frame tracking", osc, front,
                                  setup, s, 0.8, n, false));
  timings.push_back(planar_timing("platform_track", "landing platform 1.0 m below the bottom camera: tracking",
                                  setup.lab.platform, bottom, setup, s, 1.0, n, false));
  timings.push_back(slam_timing(s, front, n));
  timings.push_back(face_timing(s, n));
  timings.push_back(head_timing(n));
  timings.push_back(head_reacquire_timing(n));
  return timings;
}

}  // namespace

int run_bench_vision_command(const ParsedArgs& args) {
  const int n = args.integer_or("--frames", 100, 5, 100000);
  const std::string part = args.value_or("--part", "all");
  if (part != "all" && part != "cases" && part != "detectors") {
    throw UsageError("--part must be cases, detectors or all, not '" + part + "'");
  }
  const std::filesystem::path config = args.value_or("--config", (source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(config)) throw UsageError("--config " + config.string() + ": no such file");
  const ConfigDocument doc = ConfigDocument::load(config);
  const fusion::FrontEndSettings s = fusion::read_front_end_settings(doc.root(), config.parent_path());
  control::FlightStackSetup setup;
  if (doc.root().has("vision")) setup.vision = read_vision_thresholds(doc.root().object("vision"));
  setup.lab = fusion::lab_geometry_from(load_lab_description(default_lab_path()));

  const std::vector<Timing> timings = part == "detectors" ? std::vector<Timing>{} : run_cases(setup, s, n);
  const std::vector<DetectorRow> detectors =
      part == "cases" ? std::vector<DetectorRow>{}
                      : compare_detectors(*setup.lab.find_instrument("oscilloscope"), PinholeCamera::ardrone2_front(), setup.vision,
                                          s.planar, std::min(n, 60));
  if (args.flag("--json")) {
    nlohmann::json out{{"cases", nlohmann::json::array()}, {"detectors", nlohmann::json::array()}};
    for (const Timing& t : timings) {
      nlohmann::json j{{"case", t.name}, {"what", t.what}, {"frames", t.times.size()}, {"with_result", t.ok}};
      j.update(times_json(t.times));
      out["cases"].push_back(j);
    }
    for (const DetectorRow& d : detectors) {
      nlohmann::json j{{"range", d.range}, {"detector", d.name}, {"config", nlohmann::json::parse(d.config)},
                       {"default", d.is_default}, {"frames", d.frames}, {"found", d.found}, {"load_ms", d.load_ms}};
      j.update(times_json(d.times));
      out["detectors"].push_back(j);
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (!timings.empty()) {
    std::printf("%-20s %20s | %20s | %6s %9s  %s\n", "case", "cpu median p95 max", "wall median p95 max", "first", "result", "what");
    for (const Timing& t : timings) {
      std::printf("%-20s ", t.name.c_str());
      print_times(t.times);
      std::printf(" %4d/%-4zu  %s\n", t.ok, t.times.size(), t.what.c_str());
    }
  }
  if (!detectors.empty()) {
    std::printf("\n%-5s %-24s %20s | %20s | %6s %7s %7s\n", "range", "detector", "cpu median p95 max", "wall median p95 max", "first",
                "found", "load");
    for (const DetectorRow& d : detectors) {
      std::printf("%-5s %-24s ", d.range.c_str(), (d.name + (d.is_default ? " *" : "")).c_str());
      print_times(d.times);
      std::printf(" %3d/%-3d %7.0f\n", d.found, d.frames, d.load_ms);
    }
    std::printf("* the configuration's detector. Each frame a detection with the predicted distance; first: the first frame's cpu ms.\n");
  }
  std::printf("ms per frame on this machine (cpu: this thread's CPU time; wall: elapsed); the video runs at 30 fps (33 ms per frame).\n");
  return 0;
}

}  // namespace labo::bench
