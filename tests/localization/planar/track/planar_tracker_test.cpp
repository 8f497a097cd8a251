#include <catch2/catch.hpp>

#include <opencv2/imgproc.hpp>

#include "localization/planar/track/ecc_tracker.hpp"
#include "localization/planar/track/ic_tracker.hpp"
#include "localization/planar/planar_template.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

struct PerturbedScene {
  cv::Mat scene;
  cv::Matx33d H0, H_true;
  std::array<cv::Point2d, 4> truth;
};

const std::array<cv::Point2d, 4> kCorners{cv::Point2d(-0.5, -0.5), cv::Point2d(199.5, -0.5), cv::Point2d(199.5, 199.5),
                                          cv::Point2d(-0.5, 199.5)};

PerturbedScene perturbed_scene(const cv::Mat& templ, double sigma, std::uint64_t seed) {
  PerturbedScene p;
  cv::RNG rng(seed);
  p.H0 = cv::Matx33d(1, 0, 220, 0, 1, 140, 0, 0, 1);
  const auto base = map_corners(p.H0, kCorners);
  std::array<cv::Point2f, 4> src, dst;
  for (std::size_t i = 0; i < 4; ++i) {
    p.truth[i] = base[i] + cv::Point2d(rng.gaussian(sigma), rng.gaussian(sigma));
    src[i] = cv::Point2f(kCorners[i]);
    dst[i] = cv::Point2f(p.truth[i]);
  }
  p.H_true = cv::getPerspectiveTransform(src.data(), dst.data());
  p.scene = make_clutter_background(cv::Size(640, 480), static_cast<std::uint32_t>(seed) + 100);
  draw_template(templ, p.H_true, p.scene);
  return p;
}

}  // namespace

TEST_CASE("planar: LaboDrone's tracker recovers a known homography to a tenth of a pixel") {
  const cv::Mat templ = make_procedural_panel(cv::Size(200, 200), 7);
  planar::InverseCompositionalTracker tracker(templ, planar::PlanarConfig{});
  int converged = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const PerturbedScene p = perturbed_scene(templ, 8.0, seed);
    const planar::HomographyTrackOutcome o = tracker.track(p.scene, p.H0);
    const double rms = corner_rms(map_corners(o.H, kCorners), p.truth);
    if (o.converged && rms < 0.15) ++converged;
    CHECK(o.correlation > 0.95);
  }
  CHECK(converged >= 9);
}

TEST_CASE("planar: OpenCV's ECC wrapper recovers a known homography") {
  const cv::Mat templ = make_procedural_panel(cv::Size(200, 200), 7);
  planar::EccTracker tracker(templ, planar::PlanarConfig{});
  const PerturbedScene p = perturbed_scene(templ, 5.0, 3);
  const planar::HomographyTrackOutcome o = tracker.track(p.scene, p.H0);
  REQUIRE(o.converged);
  CHECK(corner_rms(map_corners(o.H, kCorners), p.truth) < 0.5);
  CHECK(o.correlation > 0.95);
}

TEST_CASE("planar: the tracker ignores brightness and contrast changes") {
  const cv::Mat templ = make_procedural_panel(cv::Size(200, 200), 7);
  planar::InverseCompositionalTracker tracker(templ, planar::PlanarConfig{});
  PerturbedScene p = perturbed_scene(templ, 6.0, 4);
  cv::Mat dim;
  p.scene.convertTo(dim, CV_8U, 0.45, 60);  // gain 0.45, bias +60 grey levels
  const planar::HomographyTrackOutcome o = tracker.track(dim, p.H0);
  REQUIRE(o.converged);
  CHECK(corner_rms(map_corners(o.H, kCorners), p.truth) < 0.2);
  CHECK(o.correlation > 0.9);
}

TEST_CASE("planar: trackers report failure instead of throwing on an unrelated image") {
  const cv::Mat templ = make_procedural_panel(cv::Size(200, 200), 7);
  cv::Mat noise(480, 640, CV_8UC1);
  cv::RNG(9).fill(noise, cv::RNG::UNIFORM, 0, 256);
  const cv::Matx33d H0(1, 0, 220, 0, 1, 140, 0, 0, 1);
  for (planar::TrackerKind kind : {planar::TrackerKind::Ecc, planar::TrackerKind::InverseCompositional}) {
    auto tracker = make_homography_tracker(kind, templ, planar::PlanarConfig{});
    planar::HomographyTrackOutcome o;
    REQUIRE_NOTHROW(o = tracker->track(noise, H0));
    CHECK((!o.converged || o.correlation < 0.5));
  }
  // A prior entirely outside the frame.
  auto ic = make_homography_tracker(planar::TrackerKind::InverseCompositional, templ, planar::PlanarConfig{});
  const planar::HomographyTrackOutcome out = ic->track(noise, cv::Matx33d(1, 0, 5000, 0, 1, 5000, 0, 0, 1));
  CHECK_FALSE(out.converged);
  CHECK(std::string(out.failure) == "object out of view");
}
