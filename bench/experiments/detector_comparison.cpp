#include "bench/experiments/detector_comparison.hpp"

#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "bench/planar/synthetic_scene.hpp"
#include "localization/fusion/planar_front_end.hpp"

namespace labo::bench {

namespace {

constexpr double kFps = 30.0;
constexpr double kGolden = 0.6180339887;

struct View {
  cv::Mat frame;
  double predicted_distance_m = 0;
};

// Views from distances spread over [near_m, far_m] (a low-discrepancy order), off the panel's axis
// by up to a quarter of the distance, rolled by up to `max_roll_rad`.
std::vector<View> views(const fusion::PlanarTarget& target, const PinholeCamera& camera, double near_m, double far_m,
                        double max_roll_rad, int n) {
  const cv::Mat templ = cv::imread(target.template_path.string(), cv::IMREAD_GRAYSCALE);
  if (templ.empty()) throw std::runtime_error("bench vision: cannot read " + target.template_path.string());
  const PlanarViewRenderer renderer(camera, make_clutter_background(cv::Size(1600, 1600), 31), 0.0025);
  std::vector<View> out;
  for (int i = 0; i < n; ++i) {
    const double u = std::fmod(0.5 + kGolden * i, 1.0);
    const double d = near_m + (far_m - near_m) * u;
    const Eigen::Vector3d eye(0.25 * d * std::sin(1.3 * i), 0.08 * d * std::cos(0.7 * i), -d);
    const Eigen::Vector3d look(0.6 * eye.x(), 0.6 * eye.y(), 0);
    View v;
    v.frame = renderer.render(templ, target.width_m, target.height_m, look_at_object(eye, look, max_roll_rad * std::sin(2.3 * i)));
    v.predicted_distance_m = eye.norm() * (1.0 + 0.08 * std::sin(2.1 * i));
    out.push_back(std::move(v));
  }
  return out;
}

struct Variant {
  std::string name, config;
  std::function<void(planar::PlanarConfig&)> apply;
};

bool same_detector(const planar::PlanarConfig& a, const planar::PlanarConfig& b, bool far) {
  if (far) return a.template_search == b.template_search;
  return a.near_detector == b.near_detector && a.near_frame_scale == b.near_frame_scale;
}

DetectorRow run_variant(const std::string& range, const Variant& v, const std::vector<View>& frames,
                        const fusion::PlanarTarget& target, const PinholeCamera& camera, const VisionThresholds& vision,
                        const planar::PlanarConfig& base) {
  planar::PlanarConfig config = base;
  v.apply(config);
  DetectorRow row{range, v.name, v.config, same_detector(config, base, range == "far"), 0, 0, 0, {}};
  std::unique_ptr<fusion::PlanarFrontEnd> fe;
  row.load_ms = time_call([&] { fe = std::make_unique<fusion::PlanarFrontEnd>(target, camera, vision, config); }).wall_ms;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    fe->reset();
    const fusion::TargetObservation* o = nullptr;
    row.times.add(time_call([&] { o = &fe->process(frames[i].frame, static_cast<double>(i) / kFps, frames[i].predicted_distance_m); }));
    ++row.frames;
    row.found += o->state == fusion::TrackState::Tracking ? 1 : 0;
  }
  return row;
}

}  // namespace

std::vector<DetectorRow> compare_detectors(const fusion::PlanarTarget& target, const PinholeCamera& camera,
                                           const VisionThresholds& vision, const planar::PlanarConfig& config, int frames) {
  using planar::NearDetector;
  using planar::TemplateSearch;
  const double lambda = target.sift_switch_distance_m.value_or(vision.sift_switch_distance_m);
  const std::vector<Variant> far{
      {"template per_scale", R"({"template_search": "per_scale"})", [](planar::PlanarConfig& c) { c.template_search = TemplateSearch::PerScale; }},
      {"template coarse_to_fine", R"({"template_search": "coarse_to_fine"})",
       [](planar::PlanarConfig& c) { c.template_search = TemplateSearch::CoarseToFine; }},
  };
  const auto near_variant = [](std::string name, NearDetector kind, double scale) {
    const std::string config = std::string(R"({"near_detector": ")") + planar::to_string(kind) + R"(", "near_frame_scale": )" +
                               (scale < 1 ? "0.5" : "1") + "}";
    return Variant{std::move(name), config, [kind, scale](planar::PlanarConfig& c) {
                     c.near_detector = kind;
                     c.near_frame_scale = scale;
                   }};
  };
  const std::vector<Variant> near{
      near_variant("sift", NearDetector::Sift, 1.0),   near_variant("sift half", NearDetector::Sift, 0.5),
      near_variant("orb", NearDetector::Orb, 1.0),     near_variant("orb half", NearDetector::Orb, 0.5),
      near_variant("brisk", NearDetector::Brisk, 1.0), near_variant("akaze", NearDetector::Akaze, 1.0),
  };
  std::vector<DetectorRow> rows;
  const std::vector<View> far_views = views(target, camera, lambda + 0.1, lambda + 1.9, 0.05, frames);
  for (const Variant& v : far) rows.push_back(run_variant("far", v, far_views, target, camera, vision, config));
  const std::vector<View> near_views = views(target, camera, 0.5, lambda - 0.1, 0.35, frames);
  for (const Variant& v : near) rows.push_back(run_variant("near", v, near_views, target, camera, vision, config));
  return rows;
}

}  // namespace labo::bench
