#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "core/config_reader.hpp"
#include "localization/planar/planar_template.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;
using labo::test::ScratchDir;

namespace {

std::string refusal(const cv::Mat& image, double w = 0.4, double h = 0.3) {
  try {
    planar::PlanarTemplate::create(image, w, h, "t", planar::PlanarConfig{});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("planar: templates are refused with the reason") {
  const cv::Mat good = make_procedural_panel(cv::Size(160, 120), 1);
  CHECK(refusal(good).empty());
  CHECK(refusal(cv::Mat()) == "template 't' refused: the image is empty");
  CHECK(refusal(good(cv::Rect(0, 0, 31, 40))).find("at least 32 px") != std::string::npos);
  CHECK(refusal(cv::Mat(100, 100, CV_8UC1, cv::Scalar(128))).find("too little texture") != std::string::npos);
  cv::Mat stripes(100, 100, CV_8UC1);
  for (int x = 0; x < 100; ++x) stripes.col(x).setTo((x / 5) % 2 ? 200 : 40);
  CHECK(refusal(stripes).find("edges run in one direction") != std::string::npos);
  CHECK(refusal(good, 0.0, 0.3).find("must be positive") != std::string::npos);
  CHECK(refusal(good, 0.4, -1.0).find("must be positive") != std::string::npos);
  CHECK(refusal(good, std::nan(""), 0.3).find("must be positive") != std::string::npos);
}

TEST_CASE("planar: unreadable template files are refused") {
  const ScratchDir scratch("planar_template");
  const std::filesystem::path& dir = scratch.path();
  std::ofstream(dir / "junk.png") << "not a png";
  auto message = [](const std::filesystem::path& p) {
    try {
      planar::PlanarTemplate::load(p, 0.4, 0.3, planar::PlanarConfig{});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(message(dir / "missing.png").find("no such file") != std::string::npos);
  CHECK(message(dir / "junk.png").find("not a readable image") != std::string::npos);
}

TEST_CASE("planar: large photos are downscaled with an exact pixel map") {
  const cv::Mat big = make_procedural_panel(cv::Size(960, 640), 2);
  const planar::PlanarTemplate t = planar::PlanarTemplate::create(big, 0.6, 0.4, "big", planar::PlanarConfig{});
  CHECK(t.working().cols == 320);
  CHECK(t.original_size() == cv::Size(960, 640));
  // The original's outer corner maps to the working image's outer corner.
  const cv::Point2d c = apply_homography(t.working_from_original(), cv::Point2d(959.5, 639.5));
  CHECK(c.x == Approx(319.5));
  CHECK(c.y == Approx(212.8333).epsilon(0.01));
}

TEST_CASE("planar: the planar config section is validated") {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      const ConfigDocument doc = ConfigDocument::parse(text, "p.json");
      read_planar_config(doc.root());
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  CHECK(error_of(R"({"tracker": "ecc", "pyramid_levels": 4})").empty());
  CHECK(error_of(R"({"tracker": "lk"})").find("tracker") != std::string::npos);
  CHECK(error_of(R"({"pyramid_levels": 9})").find("pyramid_levels") != std::string::npos);
  CHECK(error_of(R"({"ecc_gauss_size": 4})").find("odd") != std::string::npos);
  CHECK(error_of(R"({"detection_min_width_fraction": 0.5, "detection_max_width_fraction": 0.4})").find("exceed") !=
        std::string::npos);
  CHECK(error_of(R"({"trackr": "ic"})").find("trackr") != std::string::npos);
  CHECK(error_of(R"({"pose_refinement": "ippe"})").find("pose_refinement") != std::string::npos);
  CHECK(error_of(R"({"se3_covariance_inflation": 0})").find("se3_covariance_inflation") != std::string::npos);
  CHECK(error_of(R"({"pose_refinement": "none", "se3_iterations": 4})").empty());
  CHECK(error_of(R"({"se3_template_resolution": "native"})").find("se3_template_resolution") != std::string::npos);
  const ConfigDocument doc = ConfigDocument::parse(R"({"tracker": "ecc"})", "p.json");
  CHECK(read_planar_config(doc.root()).tracker == planar::TrackerKind::Ecc);
  CHECK_FALSE(read_planar_config(doc.root()).se3.resample_to_frame);
  const ConfigDocument frame = ConfigDocument::parse(R"({"se3_template_resolution": "frame"})", "p.json");
  CHECK(read_planar_config(frame.root()).se3.resample_to_frame);
  CHECK(error_of(R"({"se3_pixel_model": "box"})").find("se3_pixel_model") != std::string::npos);
  CHECK(error_of(R"({"se3_footprint_max_width_px": 0})").find("se3_footprint_max_width_px") != std::string::npos);
  CHECK(read_planar_config(doc.root()).se3_footprint_model);
  const ConfigDocument sampled =
      ConfigDocument::parse(R"({"se3_pixel_model": "sampled", "se3_footprint_max_width_px": 150})", "p.json");
  CHECK_FALSE(read_planar_config(sampled.root()).se3_footprint_model);
  CHECK(read_planar_config(sampled.root()).se3_footprint_max_width_px == 150.0);
}
