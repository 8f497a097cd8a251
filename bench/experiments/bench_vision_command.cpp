#include "bench/experiments/bench_vision_command.hpp"

#include "control/flight_stack.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "localization/fusion/face_front_end.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "localization/fusion/lab_geometry.hpp"
#include "localization/fusion/planar_front_end.hpp"
#include "localization/fusion/slam_front_end.hpp"
#include "core/candide3.hpp"
#include "core/config_reader.hpp"
#include "core/source_tree.hpp"
#include "drone/lab/lab_description.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "bench/slam/bench_flights.hpp"
#include "bench/slam/synthetic_room.hpp"

namespace labo {

namespace {

// Wall time of one call, for this benchmark's figures only (never fed to an algorithm).
double ms_of(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct Timing {
  std::string name, what;
  std::vector<double> ms;
  int ok = 0;  // frames with a result (tracking / pose)
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

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
  fusion::PlanarFrontEnd fe(target, camera, setup.vision, s.planar);
  const auto frames = panel_views(target, camera, distance, n + 2);
  for (int i = 0; i < 2 && !detect_every_frame; ++i) fe.process(frames[static_cast<std::size_t>(i)], i / 30.0, distance);  // warm up
  for (int i = 2; i < n + 2; ++i) {
    if (detect_every_frame) fe.reset();
    const fusion::TargetObservation* o = nullptr;
    t.ms.push_back(ms_of([&] { o = &fe.process(frames[static_cast<std::size_t>(i)], i / 30.0, distance); }));
    t.ok += o->state == fusion::TrackState::Tracking ? 1 : 0;
  }
  return t;
}

Timing slam_timing(const fusion::FrontEndSettings& s, const PinholeCamera& camera, int n) {
  Timing t{"slam_track", "SLAM front-end, synthetic room approach flight, frames after initialization", {}, 0};
  slam::SlamSettings settings = s.slam;
  settings.mapping_mode = slam::MappingMode::Threaded;  // as the server runs it: mapping off the frame path
  fusion::SlamSystemFrontEnd fe(std::make_unique<slam::SlamSystem>(camera, settings));
  const slam::SyntheticRoom room(camera);
  const slam::Flight flight = slam::approach_flight(room.panel_center());
  for (std::size_t i = 0; i < flight.frames.size() && static_cast<int>(t.ms.size()) < n; ++i) {
    const cv::Mat img = room.render(flight.frames[i].T_world_cam, static_cast<unsigned>(i));
    const fusion::SlamFrame* f = nullptr;
    const double ms = ms_of([&] { f = &fe.process(img, flight.frames[i].t, std::nullopt); });
    if (f->summary.state == fusion::SlamState::Initializing) continue;
    t.ms.push_back(ms);
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
    const double ms = ms_of([&] { o = &fe.process(img, i / 30.0, std::nullopt); });
    if (i < 3) continue;  // first detection
    t.ms.push_back(ms);
    t.ok += o->state == fusion::TrackState::Tracking ? 1 : 0;
  }
  return t;
}

}  // namespace

const CommandSpec& bench_vision_command_spec() {
  static const CommandSpec spec{
      "bench vision",
      "",
      "per-frame cost of the vision front-ends flight control runs (planar detection and tracking, SLAM, face)",
      {{"--frames", "N", "frames per case (default 100)"},
       {"--json", "", "print the figures as JSON"},
       {"--config", "FILE", "configuration for the planar, slam, face and vision sections (default config/default.json)"}},
      0,
      0};
  return spec;
}

int run_bench_vision_command(const ParsedArgs& args) {
  const int n = args.integer_or("--frames", 100, 5, 100000);
  const std::filesystem::path config = args.value_or("--config", (source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(config)) throw UsageError("--config " + config.string() + ": no such file");
  const ConfigDocument doc = ConfigDocument::load(config);
  const fusion::FrontEndSettings s = fusion::read_front_end_settings(doc.root(), config.parent_path());
  control::FlightStackSetup setup;
  if (doc.root().has("vision")) setup.vision = read_vision_thresholds(doc.root().object("vision"));
  setup.lab = fusion::lab_geometry_from(load_lab_description(default_lab_path()));
  const fusion::PlanarTarget& osc = *setup.lab.find_instrument("oscilloscope");
  const PinholeCamera front = PinholeCamera::ardrone2_front(), bottom = PinholeCamera::ardrone2_bottom();

  std::vector<Timing> timings;
  timings.push_back(planar_timing("planar_detect_far", "oscilloscope at 2.8 m: template matching + tracker refinement", osc,
                                  front, setup, s, 2.8, std::min(n, 30), true));
  timings.push_back(planar_timing("planar_detect_near", "oscilloscope at 1.2 m: SIFT + tracker refinement", osc, front, setup, s,
                                  1.2, std::min(n, 30), true));
  timings.push_back(planar_timing("planar_track", "oscilloscope at 0.8 m (the standoff): frame-to-frame tracking", osc, front,
                                  setup, s, 0.8, n, false));
  timings.push_back(planar_timing("platform_track", "landing platform 1.0 m below the bottom camera: tracking",
                                  setup.lab.platform, bottom, setup, s, 1.0, n, false));
  timings.push_back(slam_timing(s, front, n));
  timings.push_back(face_timing(s, n));

  nlohmann::json out = nlohmann::json::array();
  for (const Timing& t : timings) {
    out.push_back({{"case", t.name}, {"what", t.what}, {"frames", t.ms.size()}, {"with_result", t.ok},
                   {"median_ms", quantile(t.ms, 0.5)}, {"p95_ms", quantile(t.ms, 0.95)}, {"max_ms", quantile(t.ms, 1.0)}});
  }
  if (args.flag("--json")) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%-20s %7s %7s %7s %9s  %s\n", "case", "median", "p95", "max", "result", "what");
  for (const Timing& t : timings) {
    std::printf("%-20s %6.1f  %6.1f  %6.1f  %4d/%-4zu  %s\n", t.name.c_str(), quantile(t.ms, 0.5), quantile(t.ms, 0.95),
                quantile(t.ms, 1.0), t.ok, t.ms.size(), t.what.c_str());
  }
  std::printf("ms per frame, wall time on this machine; the video runs at 30 fps (33 ms per frame).\n");
  return 0;
}

}  // namespace labo
