#include <catch2/catch.hpp>

#include <cmath>
#include <tuple>

#include "localization/planar/planar_localizer.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

constexpr double kW = 0.40, kH = 0.30;

struct Rig {
  PinholeCamera camera = PinholeCamera::ardrone2_front();
  cv::Mat panel = make_procedural_panel(cv::Size(320, 240), 11);
  PlanarViewRenderer renderer{camera, make_clutter_background(cv::Size(1200, 1200), 21), 0.0025};
  planar::PlanarConfig config;

  planar::PlanarObjectLocalizer localizer() const {
    return PlanarObjectLocalizer(planar::PlanarTemplate::create(panel, kW, kH, "panel", config), camera,
                                 planar::PlanarObjectThresholds::from(VisionThresholds{}), config);
  }
  cv::Mat view(const Eigen::Isometry3d& T) const { return renderer.render(panel, kW, kH, T); }
};

Eigen::Isometry3d at(double x, double y, double distance) {
  return look_at_object(Eigen::Vector3d(x, y, -distance), Eigen::Vector3d(0.5 * x, 0.5 * y, 0));
}

double percent_error(const planar::PlanarResult& r, const Eigen::Isometry3d& truth) {
  return 100 * (r.T_cam_object.translation() - truth.translation()).norm() / truth.translation().norm();
}

double deg_error(const planar::PlanarResult& r, const Eigen::Isometry3d& truth) {
  return rotation_angle(r.T_cam_object.linear(), truth.linear()) * 180 / 3.14159265358979;
}

}  // namespace

TEST_CASE("planar: detection and tracking give the pose of synthetic views (distorted front camera)") {
  const Rig rig;
  for (const double distance : {0.8, 1.6}) {
    planar::PlanarObjectLocalizer loc = rig.localizer();
    const Eigen::Isometry3d T0 = at(0.1, -0.05, distance);
    const planar::PlanarResult first = loc.process(rig.view(T0), 0.0);
    REQUIRE(first.state == planar::PlanarState::Detected);
    CHECK(percent_error(first, T0) < 1.0);
    CHECK(deg_error(first, T0) < 3.0);
    // A few frames of slow motion are tracked.
    for (int i = 1; i <= 4; ++i) {
      const Eigen::Isometry3d T = at(0.1 + 0.01 * i, -0.05, distance - 0.01 * i);
      const planar::PlanarResult r = loc.process(rig.view(T), i / 30.0);
      REQUIRE(r.state == planar::PlanarState::Tracking);
      CHECK(r.has_pose);
      CHECK(percent_error(r, T) < 1.0);
      CHECK(deg_error(r, T) < 3.0);
      CHECK(r.quality > 0.3);
      CHECK(r.correlation > 0.8);
      // The corners are reported in the raw (distorted) frame: the true panel corner projects there.
      const auto corner = rig.camera.project(T * Eigen::Vector3d(-kW / 2, -kH / 2, 0));
      REQUIRE(corner);
      CHECK(std::hypot(r.image_corners[0].x - corner->x(), r.image_corners[0].y - corner->y()) < 1.5);
    }
  }
}

TEST_CASE("planar: near detection uses features, far detection template matching") {
  const Rig rig;
  planar::PlanarObjectLocalizer near = rig.localizer();
  const planar::PlanarResult a = near.process(rig.view(at(0.0, 0.0, 0.9)), 0.0, 0.9);  // below lambda = 2 m
  REQUIRE(a.state == planar::PlanarState::Detected);
  CHECK(a.method == planar::PlanarMethod::Features);
  CHECK(a.inliers >= 20);
  planar::PlanarObjectLocalizer far = rig.localizer();
  const planar::PlanarResult b = far.process(rig.view(at(0.0, 0.0, 2.6)), 0.0, 2.6);
  REQUIRE(b.state == planar::PlanarState::Detected);
  CHECK(b.method == planar::PlanarMethod::TemplateMatching);
  CHECK(percent_error(b, at(0.0, 0.0, 2.6)) < 1.5);
}

TEST_CASE("planar: a loss is declared on a garbage frame and recovered at once when the panel is back") {
  const Rig rig;
  planar::PlanarObjectLocalizer loc = rig.localizer();
  const Eigen::Isometry3d T = at(0.05, 0.0, 1.2);
  REQUIRE(loc.process(rig.view(T), 0.0).state == planar::PlanarState::Detected);
  REQUIRE(loc.process(rig.view(T), 1 / 30.0).state == planar::PlanarState::Tracking);
  cv::Mat garbage(360, 640, CV_8UC1);
  cv::RNG(3).fill(garbage, cv::RNG::UNIFORM, 0, 256);
  const planar::PlanarResult lost = loc.process(garbage, 2 / 30.0);
  CHECK(lost.state == planar::PlanarState::Lost);
  CHECK_FALSE(lost.has_pose);
  CHECK((lost.reason == planar::PlanarLoss::LowCorrelation || lost.reason == planar::PlanarLoss::NoConvergence));
  // Fig. 3: the next frame runs detection again (features here: the last pose is near and recent).
  const planar::PlanarResult back = loc.process(rig.view(T), 3 / 30.0);
  REQUIRE(back.state == planar::PlanarState::Detected);
  CHECK(back.method == planar::PlanarMethod::Features);
  CHECK(percent_error(back, T) < 1.0);
}

TEST_CASE("planar: a jump of more than D between frames is a loss") {
  const Rig rig;
  planar::PlanarObjectLocalizer loc = rig.localizer();
  REQUIRE(loc.process(rig.view(at(0.0, 0.0, 2.4)), 0.0).has_pose);
  // 0.35 m closer in one frame: the tracker follows the scale change, the jump test refuses it.
  const planar::PlanarResult r = loc.process(rig.view(at(0.0, 0.0, 2.05)), 1 / 30.0);
  CHECK(r.state == planar::PlanarState::Lost);
  CHECK(r.reason == planar::PlanarLoss::PoseJump);
  // A move of 0.1 m is accepted.
  planar::PlanarObjectLocalizer slow = rig.localizer();
  REQUIRE(slow.process(rig.view(at(0.0, 0.0, 2.4)), 0.0).has_pose);
  CHECK(slow.process(rig.view(at(0.0, 0.0, 2.3)), 1 / 30.0).state == planar::PlanarState::Tracking);
}

TEST_CASE("planar: a panel half out of view gives a loss or a degraded quality, never a wrong pose") {
  const Rig rig;
  planar::PlanarObjectLocalizer loc = rig.localizer();
  double x = 0.0;
  REQUIRE(loc.process(rig.view(at(x, 0, 1.0)), 0.0).has_pose);
  // Slide sideways until the panel leaves the image.
  for (int i = 1; i <= 40; ++i) {
    x += 0.02;
    const Eigen::Isometry3d T = look_at_object(Eigen::Vector3d(x, 0, -1.0), Eigen::Vector3d(x, 0, 0));
    const Eigen::Isometry3d T_view = look_at_object(Eigen::Vector3d(x, 0, -1.0), Eigen::Vector3d(x + 0.0, 0, 0));
    (void)T_view;
    const planar::PlanarResult r = loc.process(rig.view(T), i / 30.0);
    if (r.has_pose) {
      CHECK(percent_error(r, T) < 2.0);
      CHECK(deg_error(r, T) < 5.0);
      if (r.visible_fraction < 0.99) CHECK(r.quality < 0.99 * r.visible_fraction + 1e-9);
    }
  }
  // By now the panel is out of the image: no pose.
  CHECK_FALSE(loc.process(rig.view(look_at_object(Eigen::Vector3d(1.5, 0, -1.0), Eigen::Vector3d(1.5, 0, 0))), 2.0).has_pose);
}

TEST_CASE("planar: the landing platform is localized in the bottom camera") {
  const PinholeCamera bottom = PinholeCamera::ardrone2_bottom();
  const cv::Mat pattern = make_procedural_panel(cv::Size(256, 256), 12);
  const PlanarViewRenderer renderer(bottom, make_clutter_background(cv::Size(1200, 1200), 22), 0.0025, 0.02);
  planar::PlanarObjectLocalizer loc(planar::PlanarTemplate::create(pattern, 0.6, 0.6, "platform", planar::PlanarConfig{}), bottom,
                            planar::PlanarObjectThresholds::from(VisionThresholds{}), planar::PlanarConfig{});
  const Eigen::Isometry3d T = look_at_object(Eigen::Vector3d(0.1, 0.05, -1.2), Eigen::Vector3d(0.1, 0.05, 0), 0.3);
  const planar::PlanarResult r = loc.process(renderer.render(pattern, 0.6, 0.6, T), 0.0);
  REQUIRE(r.has_pose);
  CHECK(percent_error(r, T) < 1.0);
  CHECK(deg_error(r, T) < 2.0);
}

TEST_CASE("planar: bad frames are refused without disturbing the track") {
  const Rig rig;
  planar::PlanarObjectLocalizer loc = rig.localizer();
  const Eigen::Isometry3d T = at(0.0, 0.0, 1.0);
  REQUIRE(loc.process(rig.view(T), 0.0).has_pose);
  const planar::PlanarResult small = loc.process(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)), 0.01);
  CHECK(small.reason == planar::PlanarLoss::BadFrame);
  CHECK(std::string(small.detail) == "frame size differs from the camera's");
  CHECK_FALSE(small.has_pose);
  CHECK(loc.process(cv::Mat(), 0.02).reason == planar::PlanarLoss::BadFrame);
  CHECK(loc.process(cv::Mat(360, 640, CV_8UC3, cv::Scalar(0, 0, 0)), 0.03).reason == planar::PlanarLoss::BadFrame);
  CHECK(loc.process(rig.view(T), 0.04).state == planar::PlanarState::Tracking);
}

TEST_CASE("planar: the pose carries a rotation uncertainty that grows with the distance") {
  Rig rig;
  double previous = 0;
  for (const double distance : {0.9, 1.8, 2.7}) {
    planar::PlanarObjectLocalizer loc = rig.localizer();
    const Eigen::Isometry3d T = at(0.05, 0.02, distance);
    REQUIRE(loc.process(rig.view(T), 0.0).has_pose);
    const planar::PlanarResult r = loc.process(rig.view(T), 1 / 30.0);
    REQUIRE(r.state == planar::PlanarState::Tracking);
    CHECK(r.pose_refined);
    CHECK(deg_error(r, T) < 1.0);
    CHECK(r.rotation_sigma_rad > previous);
    CHECK(r.position_sigma_m > 0.0);
    previous = r.rotation_sigma_rad;
  }
  // Without the refinement the pose is IPPE's and the uncertainty the corners' (larger).
  rig.config.pose_refinement = planar::PoseRefinement::None;
  planar::PlanarObjectLocalizer ippe = rig.localizer();
  const Eigen::Isometry3d T = at(0.05, 0.02, 2.7);
  REQUIRE(ippe.process(rig.view(T), 0.0).has_pose);
  const planar::PlanarResult r = ippe.process(rig.view(T), 1 / 30.0);
  REQUIRE(r.has_pose);
  CHECK_FALSE(r.pose_refined);
  CHECK(r.rotation_sigma_rad > previous);
}

// The refinement fits the pixel's footprint on the raw frame (se3_pixel_model "footprint", the default)
// unless the panel is wider than se3_footprint_max_width_px or moves fast enough for the motion-blur
// model (>= 2 px between frames), which only the sampled model has.
TEST_CASE("planar: the footprint model refines the pose unless the panel is too wide or a motion blur is modelled") {
  Rig rig;
  const Eigen::Isometry3d T0 = at(0.05, 0.02, 2.2);  // ~100 px wide
  {
    planar::PlanarObjectLocalizer loc = rig.localizer();
    REQUIRE(loc.process(rig.view(T0), 0.0).state == planar::PlanarState::Detected);
    const planar::PlanarResult still = loc.process(rig.view(T0), 1 / 30.0);
    REQUIRE(still.state == planar::PlanarState::Tracking);
    CHECK(still.pose_refined);
    CHECK(still.footprint_model);
    // 1.2 deg: this renderer samples a shrunk template bilinearly, not each pixel's area, so the
    // footprint model does not describe its frames exactly (docs/planar.md).
    CHECK(deg_error(still, T0) < 2.0);
    // Sideways at 0.9 m/s: ~4 px per frame, the motion-blur search runs on the sampled model.
    const Eigen::Isometry3d T1 = at(0.08, 0.02, 2.2);
    const planar::PlanarResult moving = loc.process(rig.view(T1), 2 / 30.0);
    REQUIRE(moving.state == planar::PlanarState::Tracking);
    CHECK(moving.pose_refined);
    CHECK_FALSE(moving.footprint_model);
  }
  rig.config.se3_footprint_max_width_px = 60;
  planar::PlanarObjectLocalizer narrow = rig.localizer();
  REQUIRE(narrow.process(rig.view(T0), 0.0).state == planar::PlanarState::Detected);
  const planar::PlanarResult wide = narrow.process(rig.view(T0), 1 / 30.0);
  REQUIRE(wide.state == planar::PlanarState::Tracking);
  CHECK(wide.pose_refined);
  CHECK_FALSE(wide.footprint_model);
  rig.config.se3_footprint_model = false;
  planar::PlanarObjectLocalizer sampled = rig.localizer();
  sampled.process(rig.view(T0), 0.0);
  CHECK_FALSE(sampled.process(rig.view(T0), 1 / 30.0).footprint_model);
}

TEST_CASE("planar: a panel sliding slowly across the image's edge is fitted by the footprint model or lost, never wrongly") {
  // The test above slides ~11 px per frame, so its partly visible frames go to the sampled model (motion
  // blur modelled). Here the panel moves 1.6 px per frame (< 2 px: no blur modelled), so the footprint
  // model (AreaPoseRefiner) fits the partly visible panel: leaving the image sideways at 1 m, and entering
  // it from below at 2.5 m (detected when 84 % is in view by ORB, the default near detector; the
  // paper's SIFT found it at 60 %: ORB's 31 px patch covers most of a 91 x 45 px panel).
  const Rig rig;
  REQUIRE(rig.config.se3_footprint_model);
  struct Pass {
    double distance;
    bool sideways, leaving;
  };
  for (const Pass pass : {Pass{1.0, true, true}, Pass{2.5, false, false}}) {
    CAPTURE(pass.distance, pass.sideways, pass.leaving);
    planar::PlanarObjectLocalizer loc = rig.localizer();
    const double step = 1.6 * pass.distance / rig.camera.intrinsics().fx;  // metres per frame
    // Offsets of the panel's centre from the optical axis (m): fully in view, and 45 % in view.
    const double half = pass.sideways ? 0.5 * kW : 0.5 * kH;
    const double edge = (pass.sideways ? 0.56 : 0.40) * pass.distance;
    const double full = edge - half - 0.03, gone = edge + 0.1 * half;
    int footprint_partial = 0, lost_out_of_view = 0;
    double least_visible_with_pose = 1.0;
    for (int i = 0;; ++i) {
      const double offset = pass.leaving ? full + i * step : gone - i * step;
      if (offset > gone || offset < full) break;
      const Eigen::Vector3d camera = pass.sideways ? Eigen::Vector3d(offset, 0, -pass.distance)
                                                   : Eigen::Vector3d(0, -offset, -pass.distance);
      const Eigen::Isometry3d T = look_at_object(camera, Eigen::Vector3d(camera.x(), camera.y(), 0));
      const planar::PlanarResult r = loc.process(rig.view(T), i / 30.0);
      if (r.reason == planar::PlanarLoss::OutOfView) ++lost_out_of_view;
      if (!r.has_pose) continue;
      CAPTURE(i, r.visible_fraction, r.footprint_model);
      CHECK(r.visible_fraction >= rig.config.min_visible_fraction);
      CHECK(percent_error(r, T) < 0.5);
      CHECK(deg_error(r, T) < 1.0);  // a few tenths in practice (docs/planar.md)
      CHECK(r.quality <= r.visible_fraction + 1e-9);
      least_visible_with_pose = std::min(least_visible_with_pose, r.visible_fraction);
      if (r.visible_fraction < 0.95 && r.footprint_model) ++footprint_partial;
    }
    CHECK(footprint_partial >= 5);  // the footprint model did fit partly visible panels (7 and 66 frames)
    CHECK(least_visible_with_pose < 0.9);  // well below whole
    if (pass.leaving) CHECK(lost_out_of_view >= 1);  // and then the panel was lost, not mislocated
  }
}

// A detection that the next frame cannot follow may have been a look-alike (a part of the scene that
// matches the template at another scale): its distance must not narrow the searches after it, or the
// real panel, at another distance, is never searched for at its size.
TEST_CASE("planar: a detection lost at once does not steer the next searches") {
  const Rig rig;
  planar::PlanarObjectLocalizer loc = rig.localizer();
  REQUIRE(loc.process(rig.view(at(0.0, 0.0, 3.0)), 0.0).state == planar::PlanarState::Detected);
  cv::Mat garbage(360, 640, CV_8UC1);
  cv::RNG(4).fill(garbage, cv::RNG::UNIFORM, 0, 256);
  REQUIRE(loc.process(garbage, 1 / 30.0).state == planar::PlanarState::Lost);
  // Half the distance: twice the width, outside the window a 3 m prediction would search.
  const Eigen::Isometry3d T = at(0.0, 0.0, 1.5);
  const planar::PlanarResult back = loc.process(rig.view(T), 2 / 30.0);
  REQUIRE(back.state == planar::PlanarState::Detected);
  CHECK(percent_error(back, T) < 1.0);
}

TEST_CASE("planar: a lens the calibration lacks widens the refinement's leash by the configured calibration error") {
  // The bottom camera is configured without distortion; its lens has some (k1 = 0.05: ~4 px at the
  // image's corner). Over the platform at 0.6-0.9 m the panel fills the view, the tracker's homography
  // bends with the lens and the rigid plane's photometric fit cannot: the two part by 2-6 px, beyond
  // the 1.5 px leash, and every such frame was lost as a contradiction (the randomized world's landings
  // hovered blind). With the calibration's error configured most frames keep a pose, within 2 % of the
  // distance.
  CameraIntrinsics lens = PinholeCamera::ardrone2_bottom().intrinsics();
  lens.k1 = 0.05;
  const PinholeCamera real_lens(lens);
  const cv::Mat pattern = make_procedural_panel(cv::Size(256, 256), 12);
  const PlanarViewRenderer renderer(real_lens, make_clutter_background(cv::Size(1200, 1200), 22), 0.0025, 0.02);
  auto fly_down = [&](double calibration_error_px) {
    CameraIntrinsics configured = PinholeCamera::ardrone2_bottom().intrinsics();
    configured.calibration_error_px = calibration_error_px;
    const PinholeCamera camera(configured);
    planar::PlanarObjectLocalizer loc(planar::PlanarTemplate::create(pattern, 0.6, 0.6, "platform", planar::PlanarConfig{}),
                                      camera, planar::PlanarObjectThresholds::from(VisionThresholds{}), planar::PlanarConfig{});
    int posed = 0, frames = 0;
    double worst_percent = 0;
    for (double z = 0.9; z >= 0.6; z -= 0.01, ++frames) {
      const Eigen::Isometry3d T = look_at_object(Eigen::Vector3d(0.03, -0.02, -z), Eigen::Vector3d(0.03, -0.02, 0), 0.3);
      const planar::PlanarResult r = loc.process(renderer.render(pattern, 0.6, 0.6, T), frames / 30.0);
      if (!r.has_pose) continue;
      ++posed;
      worst_percent = std::max(worst_percent, percent_error(r, T));
    }
    return std::tuple{posed, frames, worst_percent};
  };
  const auto [posed_exact, frames, worst_exact] = fly_down(0.0);
  const auto [posed_allowed, frames_allowed, worst_allowed] = fly_down(6.0);
  WARN("posed " << posed_exact << "/" << frames << " without the calibration error (worst " << worst_exact << " %), "
                << posed_allowed << "/" << frames_allowed << " with it (worst " << worst_allowed << " %)");
  CHECK(posed_exact < frames / 2);
  CHECK(posed_allowed >= 0.8 * frames);  // 26 of 30: a few frames still part by more than the allowance
  CHECK(worst_allowed < 2.0);
}

TEST_CASE("planar: a camera's calibration error is read from the config and refused when negative") {
  CameraIntrinsics k = PinholeCamera::ardrone2_bottom().intrinsics();
  k.calibration_error_px = -1;
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("calibration_error_px"));
}
