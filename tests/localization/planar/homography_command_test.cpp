#include <catch2/catch.hpp>

#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "localization/planar/planar_commands.hpp"
#include "localization/planar/planar_template.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "tests/support/cout_capture.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  test::CoutCapture capture;
  const int rc = run_homography_command(parse_args(homography_command_spec(), args));
  if (output) *output = capture.text();
  return rc;
}

}  // namespace

TEST_CASE("planar: labodrone homography finds a panel, says when it does not, refuses bad input") {
  // Per process: two suites running at once (two worktrees) must not overwrite each other's images.
  const auto dir = std::filesystem::temp_directory_path() / ("labo_homography_cli_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const cv::Mat panel = make_procedural_panel(cv::Size(300, 200), 3);
  cv::imwrite((dir / "panel.png").string(), panel);
  cv::Mat scene = make_clutter_background(cv::Size(640, 360), 4);
  const cv::Matx33d H(0.7, 0.05, 150, -0.04, 0.7, 60, 0.0002, 0, 1);
  draw_template(panel, H, scene);
  cv::imwrite((dir / "scene.png").string(), scene);
  cv::imwrite((dir / "empty_scene.png").string(), make_clutter_background(cv::Size(640, 360), 5));
  cv::imwrite((dir / "flat.png").string(), cv::Mat(100, 100, CV_8UC1, cv::Scalar(90)));

  std::string out;
  CHECK(run({(dir / "panel.png").string(), (dir / "scene.png").string()}, &out) == 0);
  CHECK(out.find("\"found\": true") != std::string::npos);
  // The reported corner is where the true homography puts it.
  const cv::Point2d c = apply_homography(H, cv::Point2d(-0.5, -0.5));
  CHECK(out.find(std::to_string(static_cast<int>(c.x))) != std::string::npos);
  CHECK(run({(dir / "panel.png").string(), (dir / "scene.png").string(), "--method", "features"}) == 0);
  CHECK(run({(dir / "panel.png").string(), (dir / "empty_scene.png").string()}, &out) == 3);
  CHECK(out.find("\"found\": false") != std::string::npos);
  CHECK_THROWS_AS(run({(dir / "flat.png").string(), (dir / "scene.png").string()}), UsageError);
  CHECK_THROWS_AS(run({(dir / "missing.png").string(), (dir / "scene.png").string()}), UsageError);
  CHECK_THROWS_AS(run({(dir / "panel.png").string(), (dir / "missing.png").string()}), UsageError);
  CHECK_THROWS_AS(run({(dir / "panel.png").string(), (dir / "scene.png").string(), "--method", "sift"}), UsageError);
  std::filesystem::remove_all(dir);
}
