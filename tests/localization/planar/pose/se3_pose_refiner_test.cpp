#include <catch2/catch.hpp>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "localization/planar/pose/planar_pose.hpp"
#include "localization/planar/pose/se3_pose_refiner.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

constexpr double kW = 0.40, kH = 0.30, kDeg = 3.14159265358979 / 180.0;

struct Scene {
  PinholeCamera camera = PinholeCamera::ardrone2_front().without_distortion();
  cv::Mat panel = make_procedural_panel(cv::Size(320, 240), 11);
  PlanarViewRenderer renderer{camera, make_clutter_background(cv::Size(1600, 1600), 21), 0.0025};
  planar::Se3PoseRefiner refiner{panel, kW, kH, camera.K()};

  cv::Mat view(const Eigen::Isometry3d& T, double noise = 2.0, std::uint64_t seed = 1) const {
    cv::Mat frame = renderer.render(panel, kW, kH, T), noisy;
    cv::Mat n(frame.size(), CV_16SC1);
    cv::RNG(seed).fill(n, cv::RNG::NORMAL, 0, noise);
    frame.convertTo(noisy, CV_16S);
    noisy += n;
    noisy.convertTo(frame, CV_8U);
    return frame;
  }
};

// The panel turned about its own vertical axis (through its centre): its corners barely move when
// it is seen face-on, which is what leaves IPPE's tilt ill-conditioned.
Eigen::Isometry3d tilted(const Eigen::Isometry3d& T, double angle_rad) {
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T * turn;
}

}  // namespace

TEST_CASE("planar: the SE(3) refinement fixes the tilt of a panel seen face-on at range") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.0, 0.05, -2.5), Eigen::Vector3d::Zero(), 0.02);
  for (const double start_deg : {-3.0, 3.0}) {
    const Eigen::Isometry3d start = tilted(truth, start_deg * kDeg);
    REQUIRE(rotation_angle(start.linear(), truth.linear()) > 2.9 * kDeg);
    const planar::Se3Refinement r = scene.refiner.refine(scene.view(truth), start);
    REQUIRE(r.refined);
    CHECK(rotation_angle(r.T_cam_object.linear(), truth.linear()) < 0.6 * kDeg);
    CHECK((r.T_cam_object.translation() - truth.translation()).norm() < 0.01);
    CHECK(r.rotation_sigma_rad > 0.0);
    CHECK(r.rotation_sigma_rad < 2.0 * kDeg);
    CHECK(r.iterations >= 2);
  }
}

TEST_CASE("planar: the SE(3) refinement ignores brightness, contrast and a light gradient") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.2, 0.05, -2.0), Eigen::Vector3d(0.1, 0, 0), 0.05);
  cv::Mat frame = scene.view(truth), lit;
  cv::Mat gain(frame.size(), CV_32F);
  for (int x = 0; x < frame.cols; ++x) gain.col(x).setTo(0.5 + 0.6 * x / frame.cols);
  frame.convertTo(lit, CV_32F);
  lit = lit.mul(gain) + 15.0;
  lit.convertTo(frame, CV_8U);
  const planar::Se3Refinement r = scene.refiner.refine(frame, tilted(truth, 2.0 * kDeg));
  REQUIRE(r.refined);
  CHECK(rotation_angle(r.T_cam_object.linear(), truth.linear()) < 0.6 * kDeg);
}

TEST_CASE("planar: the SE(3) refinement's rotation uncertainty grows with the distance") {
  const Scene scene;
  double previous = 0;
  for (const double d : {0.8, 1.6, 3.0}) {
    const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.05, 0.05, -d), Eigen::Vector3d::Zero());
    const planar::Se3Refinement r = scene.refiner.refine(scene.view(truth), truth);
    REQUIRE(r.refined);
    CHECK(r.rotation_sigma_rad > 1.3 * previous);
    CHECK(r.position_sigma_m > 0.0);
    previous = r.rotation_sigma_rad;
  }
}

TEST_CASE("planar: the SE(3) refinement says why it keeps the starting pose") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.0, 0.0, -1.5), Eigen::Vector3d::Zero());
  const planar::Se3Refinement empty = scene.refiner.refine(cv::Mat(), truth);
  CHECK_FALSE(empty.refined);
  CHECK(std::string(empty.failure).find("CV_8UC1") != std::string::npos);
  CHECK(empty.T_cam_object.isApprox(truth));
  // The panel far out of the image.
  const Eigen::Isometry3d away = look_at_object(Eigen::Vector3d(3.0, 0.0, -1.5), Eigen::Vector3d(3.0, 0, 0));
  const planar::Se3Refinement outside = scene.refiner.refine(scene.view(truth), away);
  CHECK_FALSE(outside.refined);
  CHECK(std::string(outside.failure) == "too little of the panel in view");
  CHECK_THROWS_AS(Se3PoseRefiner(scene.panel, 0.0, kH, scene.camera.K()), std::invalid_argument);
}

TEST_CASE("planar: the SE(3) refinement smooths only where the panel is, with the same result as the whole frame") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.3, 0.05, -2.2), Eigen::Vector3d(0.1, 0, 0), 0.03);
  const Eigen::Isometry3d start = tilted(truth, 2.0 * kDeg);
  const cv::Mat frame = scene.view(truth);
  planar::Se3PoseRefiner::SmoothedFrame roi;
  scene.refiner.smooth(frame, {start}, roi);
  REQUIRE(roi.valid.area() > 0);
  CHECK(roi.valid.area() < frame.size().area() / 4);  // a 0.40 m panel at 2.2 m: a small region
  planar::Se3PoseRefiner::SmoothedFrame whole;
  cv::GaussianBlur(frame, whole.image, cv::Size(0, 0), planar::Se3RefinerSettings{}.smoothing_sigma_px);
  whole.valid = cv::Rect(0, 0, frame.cols, frame.rows);
  const planar::Se3Refinement a = scene.refiner.refine(roi, start), b = scene.refiner.refine(whole, start);
  REQUIRE(a.refined);
  REQUIRE(b.refined);
  // Equal up to the rounding of OpenCV's 8-bit blur (its vector and scalar paths split a region
  // differently from the whole frame): thousandths of a degree; stale or unsmoothed pixels would be
  // far more.
  CHECK(rotation_angle(a.T_cam_object.linear(), b.T_cam_object.linear()) < 0.01 * kDeg);
  CHECK((a.T_cam_object.translation() - b.T_cam_object.translation()).norm() < 1e-4);
  CHECK(rotation_angle(a.T_cam_object.linear(), truth.linear()) < 0.6 * kDeg);
}

TEST_CASE("planar: the SE(3) refinement never reads outside the smoothed region") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.0, 0.0, -1.5), Eigen::Vector3d::Zero());
  planar::Se3PoseRefiner::SmoothedFrame frame;
  scene.refiner.smooth(scene.view(truth), {truth}, frame);
  frame.valid = cv::Rect(0, 0, 40, 40);  // a corner of the frame, far from the panel
  const planar::Se3Refinement r = scene.refiner.refine(frame, truth);
  CHECK_FALSE(r.refined);
  CHECK(std::string(r.failure) == "too little of the panel in view");
}

TEST_CASE("planar: the SE(3) refinement models a motion blur it is told about") {
  const Scene scene;
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.1, 0.0, -1.2), Eigen::Vector3d(0.07, 0, 0));
  // The panel smeared horizontally over 9 px during the exposure, as a fast sideways pass.
  cv::Mat frame = scene.view(truth, 0.0);
  const int blur_px = 9;
  cv::filter2D(frame, frame, -1, cv::Mat::ones(1, blur_px, CV_32F) / blur_px);
  const Eigen::Isometry3d start = tilted(truth, 1.5 * kDeg);
  planar::Se3PoseRefiner::SmoothedFrame smoothed;
  scene.refiner.smooth(frame, {start}, smoothed);
  const planar::Se3Refinement modelled = scene.refiner.refine(smoothed, start, Eigen::Vector2d(blur_px, 0));
  const planar::Se3Refinement sharp = scene.refiner.refine(smoothed, start);
  REQUIRE(modelled.refined);
  const double modelled_error = rotation_angle(modelled.T_cam_object.linear(), truth.linear());
  CHECK(modelled_error < 0.5 * kDeg);
  // The sharp template against the smeared frame fits worse, and (when it converges) lands farther away.
  if (sharp.refined) {
    CHECK(modelled.residual_grey < sharp.residual_grey);
    CHECK(modelled_error < rotation_angle(sharp.T_cam_object.linear(), truth.linear()));
  }
}

TEST_CASE("planar: at range the SE(3) refinement can fit the template resampled to 1.3x the panel's apparent size") {
  const Scene scene;
  planar::Se3RefinerSettings settings;
  settings.resample_to_frame = true;
  const planar::Se3PoseRefiner refiner{scene.panel, kW, kH, scene.camera.K(), settings};
  const double fx = scene.camera.K()(0, 0);
  const Eigen::Isometry3d far = look_at_object(Eigen::Vector3d(0.0, 0.0, -2.5), Eigen::Vector3d::Zero());
  const planar::Se3Refinement a = refiner.refine(scene.view(far), tilted(far, 2.0 * kDeg));
  REQUIRE(a.refined);
  CHECK(rotation_angle(a.T_cam_object.linear(), far.linear()) < 1.0 * kDeg);
  CHECK(std::abs(refiner.last_template_size().width - 1.3 * fx * kW / 2.5) <= 1.0);
  const int builds = refiner.resample_builds();
  CHECK(builds == 1);
  // 1 % farther: the same resampled template; 8 % farther: rebuilt.
  const Eigen::Isometry3d farther = look_at_object(Eigen::Vector3d(0.0, 0.0, -2.525), Eigen::Vector3d::Zero());
  REQUIRE(refiner.refine(scene.view(farther), farther).refined);
  CHECK(refiner.resample_builds() == builds);
  const Eigen::Isometry3d further = look_at_object(Eigen::Vector3d(0.0, 0.0, -2.7), Eigen::Vector3d::Zero());
  REQUIRE(refiner.refine(scene.view(further), further).refined);
  CHECK(refiner.resample_builds() == builds + 1);
  CHECK(std::abs(refiner.last_template_size().width - 1.3 * fx * kW / 2.7) <= 1.0);
  // Near (the panel's image times 1.3 wider than half the template): a pyramid level.
  const Eigen::Isometry3d near = look_at_object(Eigen::Vector3d(0.0, 0.0, -1.0), Eigen::Vector3d::Zero());
  REQUIRE(refiner.refine(scene.view(near), near).refined);
  const int w = refiner.last_template_size().width;
  CHECK((w == 320 || w == 160));
  // The default: the pyramid level at range too.
  REQUIRE(scene.refiner.refine(scene.view(far), far).refined);
  CHECK((scene.refiner.last_template_size().width == 160 || scene.refiner.last_template_size().width == 80));
  CHECK(scene.refiner.resample_builds() == 0);
}

// The frame blurrier (or sharper) than the template level: the fit estimates the difference as a
// multiple of the template's Laplacian (template * Gaussian of variance v = template + v/2 Laplacian
// to first order) instead of reading it as a change of the panel's shape, i.e. a tilt.
TEST_CASE("planar: the SE(3) refinement estimates the frame's blur relative to the template") {
  const Scene scene;
  planar::Se3RefinerSettings fixed_settings;
  fixed_settings.estimate_blur = false;
  const planar::Se3PoseRefiner fixed{scene.panel, kW, kH, scene.camera.K(), fixed_settings};
  REQUIRE(planar::Se3RefinerSettings{}.estimate_blur);  // the default
  // 2.3 m: the 160 px level is finer than the panel's ~112 px image, and the camera is a little softer
  // than a pixel's box (an extra Gaussian of sigma 0.5 px), so the frame is blurrier than the level; with
  // the blur fixed the fit tilts the panel by more than a degree. (The renderer integrates each pixel's
  // footprint, so without the extra blur the frame is close enough to the level's blur that the fixed
  // fit is off by less than a degree: the extra blur is what makes the case.)
  const Eigen::Isometry3d near = look_at_object(Eigen::Vector3d(0.05, 0.03, -2.3), Eigen::Vector3d::Zero(), 0.02);
  cv::Mat near_frame;
  cv::GaussianBlur(scene.view(near), near_frame, cv::Size(0, 0), 0.5);
  for (const double start_deg : {-2.0, 2.0}) {
    const Eigen::Isometry3d start = tilted(near, start_deg * kDeg);
    const planar::Se3Refinement estimated = scene.refiner.refine(near_frame, start), kept = fixed.refine(near_frame, start);
    REQUIRE(estimated.refined);
    REQUIRE(kept.refined);
    CHECK(rotation_angle(estimated.T_cam_object.linear(), near.linear()) < 0.5 * kDeg);
    CHECK(rotation_angle(kept.T_cam_object.linear(), near.linear()) > 1.0 * kDeg);
    CHECK(estimated.blur_variance_px2 > 0.15);
    CHECK(kept.blur_variance_px2 == 0.0);
  }
  // 2.5-2.7 m through a softer lens (an extra Gaussian of sigma 0.7 px): the estimate grows by its
  // variance, and the tilt stays within 0.6 deg.
  for (const double d : {2.5, 2.7}) {
    const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.05, 0.03, -d), Eigen::Vector3d::Zero(), 0.02);
    const cv::Mat frame = scene.view(truth);
    cv::Mat soft;
    cv::GaussianBlur(frame, soft, cv::Size(0, 0), 0.7);
    const Eigen::Isometry3d start = tilted(truth, 2.0 * kDeg);
    const planar::Se3Refinement sharp = scene.refiner.refine(frame, start), blurred = scene.refiner.refine(soft, start);
    REQUIRE(sharp.refined);
    REQUIRE(blurred.refined);
    CHECK(blurred.blur_variance_px2 - sharp.blur_variance_px2 == Approx(0.49).margin(0.15));
    CHECK(rotation_angle(blurred.T_cam_object.linear(), truth.linear()) < 0.6 * kDeg);
  }
}
