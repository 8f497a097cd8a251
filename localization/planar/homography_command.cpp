// `labodrone homography TEMPLATE IMAGE [--method auto|template|features] [--config FILE]`: finds a
// template in a still image the way the localizer does (detector, then the tracker's refinement,
// accepted above alpha) and prints JSON. Exit 0 found, 3 not found, 2 bad input.
#include <iostream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/config_reader.hpp"
#include "localization/planar/track/homography_tracker.hpp"
#include "localization/planar/planar_commands.hpp"
#include "localization/planar/detect/planar_detectors.hpp"
#include "localization/planar/detect/template_detector.hpp"
#include "localization/planar/planar_template.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo::planar {

PlanarCommandSettings read_planar_command_settings(const ParsedArgs& args) {
  PlanarCommandSettings s;
  if (const auto file = args.value("--config")) {
    const ConfigDocument doc = ConfigDocument::load(*file);
    const ConfigReader root = doc.root();
    if (root.has("vision")) s.vision = read_vision_thresholds(root.object("vision"));
    if (root.has("planar")) s.planar = read_planar_config(root.object("planar"));
  }
  return s;
}

const CommandSpec& homography_command_spec() {
  static const CommandSpec spec{
      "homography",
      "TEMPLATE IMAGE",
      "find a planar template in an image; JSON {found, method, H, corners, inliers, score}; exit 3 if not found",
      {{"--method", "M", "auto (features, then template matching), template or features (planar.near_detector: ORB by default, SIFT)"},
       {"--config", "FILE", "read the \"vision\" and \"planar\" sections of this config (default: built-in values)"}},
      2,
      2};
  return spec;
}

int run_homography_command(const ParsedArgs& args) {
  const std::string method = args.value_or("--method", "auto");
  if (method != "auto" && method != "template" && method != "features") {
    throw UsageError("--method must be auto, template or features, not '" + method + "'");
  }
  const PlanarCommandSettings settings = read_planar_command_settings(args);
  // The physical size does not matter for a homography; 1 m keeps the template's aspect.
  PlanarTemplate templ = [&] {
    try {
      const cv::Mat probe = cv::imread(args.positionals[0], cv::IMREAD_GRAYSCALE);
      const double aspect = probe.empty() ? 1.0 : static_cast<double>(probe.rows) / probe.cols;
      return PlanarTemplate::load(args.positionals[0], 1.0, aspect, settings.planar);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }();
  const cv::Mat image = cv::imread(args.positionals[1], cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw UsageError("image '" + args.positionals[1] + "' refused: missing, unreadable or empty");
  if (image.cols < 32 || image.rows < 32) throw UsageError("image '" + args.positionals[1] + "' refused: smaller than 32 px");

  auto tracker = make_homography_tracker(settings.planar.tracker, templ.working(), settings.planar);
  TemplateMatchDetector matcher(templ.working(), image.size(), settings.planar, settings.vision.template_correlation_alpha);
  FeatureMatchDetector features(templ.working(), image.size(), settings.planar, settings.vision.sift_min_inliers);

  std::vector<std::string> order;
  if (method != "template") order.push_back("features");
  if (method != "features") order.push_back("template");
  nlohmann::json out{{"found", false}, {"method", nullptr}, {"H", nullptr}, {"corners", nullptr},
                     {"inliers", 0}, {"score", 0.0}};
  for (const auto& m : order) {
    const Detection d = m == "features" ? features.detect(image)
                                    : matcher.detect(image, settings.planar.detection_min_width_fraction * image.cols,
                                                     settings.planar.detection_max_width_fraction * image.cols);
    if (m == "features") out["inliers"] = d.inliers;
    nlohmann::json attempt{{"method", m}, {"detected", d.found}, {"detection_score", d.score}};
    if (m == "features") attempt["inliers"] = d.inliers;
    if (!d.found) {
      out["attempts"].push_back(attempt);
      continue;
    }
    const HomographyTrackOutcome o = tracker->track(image, d.H);
    attempt["refined"] = o.converged;
    attempt["correlation"] = o.correlation;
    if (!o.converged) attempt["refinement_failure"] = o.failure;
    out["attempts"].push_back(attempt);
    if (!o.converged || o.correlation < settings.vision.template_correlation_alpha) continue;
    const cv::Matx33d H = o.H * templ.working_from_original();
    const cv::Size size = templ.original_size();
    const auto corners = map_corners(H, {cv::Point2d(-0.5, -0.5), cv::Point2d(size.width - 0.5, -0.5),
                                         cv::Point2d(size.width - 0.5, size.height - 0.5),
                                         cv::Point2d(-0.5, size.height - 0.5)});
    out["found"] = true;
    out["method"] = m;
    out["H"] = std::vector<double>(H.val, H.val + 9);
    for (const auto& c : corners) out["corners"].push_back({c.x, c.y});
    out["score"] = o.correlation;
    out["detection_score"] = d.score;
    break;
  }
  std::cout << out.dump(2) << "\n";
  return out["found"].get<bool>() ? 0 : 3;
}

}  // namespace labo::planar
