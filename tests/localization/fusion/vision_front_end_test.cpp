#include <catch2/catch.hpp>

#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/fusion/face_front_end.hpp"
#include "localization/fusion/lab_pipelines_factory.hpp"
#include "localization/fusion/planar_front_end.hpp"
#include "localization/fusion/slam_front_end.hpp"
#include "core/candide3.hpp"
#include "core/frames.hpp"
#include "core/source_tree.hpp"
#include "drone/lab/lab_description.hpp"
#include "localization/face/textured_head_renderer.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "bench/slam/bench_flights.hpp"
#include "bench/slam/synthetic_room.hpp"
#include "bench/slam/trajectory_metrics.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::bench;
using namespace labo::fusion;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

const fusion::LabGeometry& lab_geometry() {
  static const fusion::LabGeometry g = fusion::lab_geometry_from(load_lab_description(default_lab_path()));
  return g;
}

double angle_between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

// A planar target of the lab drawn through a camera at a known pose, in front of a cluttered wall.
struct PanelScene {
  fusion::PlanarTarget target;
  PinholeCamera camera;
  cv::Mat templ = cv::imread(target.template_path.string(), cv::IMREAD_GRAYSCALE);
  PlanarViewRenderer renderer{camera, make_clutter_background(cv::Size(1200, 1200), 5), 0.0025};

  cv::Mat view(const Eigen::Isometry3d& T_cam_object) const {
    return renderer.render(templ, target.width_m, target.height_m, T_cam_object);
  }
};

// The front camera's pose in the world when the drone hovers at `body` (x, y, z) with `yaw`.
Eigen::Isometry3d front_camera_at(const Eigen::Vector3d& body, double yaw) {
  return make_pose(body, yaw) * T_body_cam_front();
}

VideoFrame bgr_frame(const cv::Mat& gray, Seconds t, CameraId camera) {
  VideoFrame f;
  f.t = t;
  f.camera = camera;
  cv::cvtColor(gray, f.bgr, cv::COLOR_GRAY2BGR);
  return f;
}

}  // namespace

TEST_CASE("vision front-ends: the instrument panel is detected near with SIFT, far with templates, then tracked") {
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const PanelScene scene{osc, PinholeCamera::ardrone2_front()};
  for (const double distance : {1.2, 2.8}) {
    fusion::PlanarFrontEnd fe(osc, scene.camera, VisionThresholds{}, planar::PlanarConfig{});
    INFO("distance " << distance);
    for (int i = 0; i < 4; ++i) {
      // A slow drift to the right and forward, as the drone approaches.
      const Eigen::Isometry3d truth =
          look_at_object(Eigen::Vector3d(0.05 + 0.01 * i, -0.03, -distance + 0.01 * i), Eigen::Vector3d::Zero());
      const fusion::TargetObservation& o = fe.process(scene.view(truth), i / 30.0, distance);
      REQUIRE(o.state == fusion::TrackState::Tracking);
      CHECK(o.t == Approx(i / 30.0));
      CHECK((o.T_cam_target.translation() - truth.translation()).norm() < 0.02 * distance);
      // A 0.4 m panel spans 80 px at 2.8 m: its tilt is known to a few degrees only.
      CHECK(angle_between(o.T_cam_target, truth) < (distance < 2.0 ? 2.0 : 6.0) * kDeg);
      CHECK(o.quality > 0.2);
      REQUIRE(o.image_points.size() == 4);
      // Corners in the raw (distorted) image, clockwise from the panel's top-left.
      const auto corner = scene.camera.project(truth * Eigen::Vector3d(-osc.width_m / 2, -osc.height_m / 2, 0));
      REQUIRE(corner);
      CHECK(std::hypot(o.image_points[0].x - corner->x(), o.image_points[0].y - corner->y()) < 2.0);
      if (i == 0) CHECK(o.method == (distance < 2.0 ? "features" : "template"));  // lambda = 2 m for the oscilloscope
      else CHECK(o.method == "ic");
    }
  }
}

TEST_CASE("vision front-ends: a panel out of view is lost with the reason, then found again") {
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const PanelScene scene{osc, PinholeCamera::ardrone2_front()};
  fusion::PlanarFrontEnd fe(osc, scene.camera, VisionThresholds{}, planar::PlanarConfig{});
  const Eigen::Isometry3d seen = look_at_object(Eigen::Vector3d(0, 0, -1.0), Eigen::Vector3d::Zero());
  REQUIRE(fe.process(scene.view(seen), 0.0, 1.0).state == fusion::TrackState::Tracking);
  cv::Mat wall = scene.view(look_at_object(Eigen::Vector3d(2.0, 0, -1.0), Eigen::Vector3d(2.0, 0, 0)));  // beside it
  const fusion::TargetObservation& lost = fe.process(wall, 1 / 30.0, 1.0);
  CHECK(lost.state == fusion::TrackState::Lost);
  CHECK_FALSE(lost.reason.empty());
  CHECK(lost.image_points.empty());
  CHECK(fe.process(scene.view(seen), 2 / 30.0, 1.0).state == fusion::TrackState::Tracking);
  // A frame that is no camera frame is refused, not posed.
  CHECK(fe.process(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), 3 / 30.0, 1.0).reason == "bad_frame");
}

TEST_CASE("vision front-ends: a wrong predicted distance costs the confirmation frames, not the target") {
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const PanelScene scene{osc, PinholeCamera::ardrone2_front()};
  fusion::PlanarFrontEnd fe(osc, scene.camera, VisionThresholds{}, planar::PlanarConfig{});
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.02, 0.0, -3.2), Eigen::Vector3d::Zero());
  const cv::Mat view = scene.view(truth);
  // Predicted at 1 m: SIFT runs, and the 70 px panel gives it too few inliers.
  const fusion::TargetObservation& first = fe.process(view, 0.0, 1.0);
  CHECK(first.state != fusion::TrackState::Tracking);
  CHECK(first.reason == "not_found");
  // The next frame runs both detectors: template matching finds it, 3.2 times farther than predicted,
  // so it counts once the tracker has followed it for 15 frames.
  const fusion::TargetObservation& second = fe.process(view, 1 / 30.0, 1.0);
  CHECK(second.state == fusion::TrackState::Lost);
  CHECK(second.reason == "unconfirmed_detection");
  int frame = 2;
  for (; frame < 30 && fe.process(view, frame / 30.0, 1.0).state != fusion::TrackState::Tracking; ++frame) {
  }
  CHECK(frame == 16);
  const fusion::TargetObservation& confirmed = fe.process(view, (frame + 1) / 30.0, 1.0);
  REQUIRE(confirmed.state == fusion::TrackState::Tracking);
  CHECK(confirmed.method != "features");
  CHECK((confirmed.T_cam_target.translation() - truth.translation()).norm() < 0.06);
}

TEST_CASE("vision front-ends: a retried detection far from the predicted distance that the tracker loses never counts") {
  // The case: the panel below the view (predicted 1.3 m), the retry's template matching finds other
  // texture at 4-6 m, tracks it for a few frames and loses it in a pose jump; it must never be
  // reported as the panel. Here: the panel at 3.2 m with a 1 m prediction, found by the retry, then
  // gone from the view.
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const PanelScene scene{osc, PinholeCamera::ardrone2_front()};
  fusion::PlanarFrontEnd fe(osc, scene.camera, VisionThresholds{}, planar::PlanarConfig{});
  const cv::Mat view = scene.view(look_at_object(Eigen::Vector3d(0.02, 0.0, -3.2), Eigen::Vector3d::Zero()));
  const cv::Mat empty = scene.view(look_at_object(Eigen::Vector3d(0.02, 0.0, -3.2), Eigen::Vector3d(6.0, 0.0, 0.0)));
  CHECK(fe.process(view, 0.0, 1.0).state != fusion::TrackState::Tracking);
  CHECK(fe.process(view, 1 / 30.0, 1.0).state != fusion::TrackState::Tracking);  // found, not confirmed
  CHECK(fe.process(view, 2 / 30.0, 1.0).state != fusion::TrackState::Tracking);  // followed, not confirmed yet
  bool ever = false;
  for (int frame = 3; frame < 30; ++frame) ever |= fe.process(empty, frame / 30.0, 1.0).state == fusion::TrackState::Tracking;
  CHECK_FALSE(ever);
}

TEST_CASE("vision front-ends: after a lost track the predicted detector runs first, not the retry") {
  // The simulated lab after a z push: the retry's template matching found the same false match every
  // other frame and the tracker lost it the frame after; when the lost track also counted as a failed
  // detection, every frame was either that retry or that track, and SIFT (which finds the panel at the
  // predicted standoff distance) never ran. Here: a candidate 3.2 m away with a 1 m prediction.
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const PanelScene scene{osc, PinholeCamera::ardrone2_front()};
  fusion::PlanarFrontEnd fe(osc, scene.camera, VisionThresholds{}, planar::PlanarConfig{});
  const cv::Mat far = scene.view(look_at_object(Eigen::Vector3d(0.02, 0.0, -3.2), Eigen::Vector3d::Zero()));
  const cv::Mat empty = scene.view(look_at_object(Eigen::Vector3d(0.02, 0.0, -3.2), Eigen::Vector3d(6.0, 0.0, 0.0)));
  CHECK(fe.process(far, 0.0, 1.0).reason == "not_found");                   // SIFT, predicted
  CHECK(fe.process(far, 1 / 30.0, 1.0).reason == "unconfirmed_detection");  // the retry's template match
  CHECK(fe.process(empty, 2 / 30.0, 1.0).state == fusion::TrackState::Lost);        // its track is lost
  // Before: this frame was a retry again and found the candidate again ("unconfirmed_detection").
  CHECK(fe.process(far, 3 / 30.0, 1.0).reason == "not_found");              // SIFT, predicted
  CHECK(fe.process(far, 4 / 30.0, 1.0).reason == "unconfirmed_detection");  // then the retry
  // And the panel where predicted is found by the predicted detector right after a lost track.
  const Eigen::Isometry3d near = look_at_object(Eigen::Vector3d(0.02, 0.0, -1.0), Eigen::Vector3d::Zero());
  CHECK(fe.process(empty, 5 / 30.0, 1.0).state == fusion::TrackState::Lost);
  const fusion::TargetObservation& found = fe.process(scene.view(near), 6 / 30.0, 1.0);
  CHECK(found.state == fusion::TrackState::Tracking);
  CHECK(found.method == "features");
}

TEST_CASE("vision front-ends: a target without a template is refused by name") {
  fusion::PlanarTarget t;
  t.id = "modelled";
  t.width_m = 0.4;
  t.height_m = 0.2;
  CHECK_THROWS_WITH(PlanarFrontEnd(t, PinholeCamera::ardrone2_front(), VisionThresholds{}, planar::PlanarConfig{}),
                    Catch::Contains("'modelled'") && Catch::Contains("no template"));
  t.template_path = "/nonexistent/panel.png";
  CHECK_THROWS_WITH(PlanarFrontEnd(t, PinholeCamera::ardrone2_front(), VisionThresholds{}, planar::PlanarConfig{}),
                    Catch::Contains("'modelled'"));
}

TEST_CASE("vision front-ends: LabPipelines runs the focused instrument on front frames and the platform on bottom frames") {
  fusion::FrontEndSettings settings;
  settings.with_face = false;
  settings.slam.mapping_mode = slam::MappingMode::Synchronous;
  const auto pipelines = fusion::make_lab_pipelines(lab_geometry(), ardrone2_cameras(), VisionThresholds{}, estimation::EstimatorConfig{}, settings);
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  // Hovering 1.3 m in front of the oscilloscope (the camera sits 0.2 m ahead of the body centre).
  const Eigen::Vector3d body = osc.T_world_object.translation() - Eigen::Vector3d(1.5, 0.05, 0.0);
  pipelines->reset(make_pose(body, 0.0), 0.0);
  const Eigen::Isometry3d T_cam_osc = front_camera_at(body, 0.0).inverse() * osc.T_world_object;
  const PanelScene panel{osc, PinholeCamera::ardrone2_front()};

  fusion::PerceptionFocus focus;
  focus.slam = false;
  pipelines->set_focus(focus);
  pipelines->on_video(bgr_frame(panel.view(T_cam_osc), 0.1, CameraId::Front));
  CHECK(pipelines->instrument().state == fusion::TrackState::Off);  // not asked for: not run

  focus.instrument_id = "oscilloscope";
  pipelines->set_focus(focus);
  pipelines->on_video(bgr_frame(panel.view(T_cam_osc), 0.2, CameraId::Front));
  const fusion::TargetObservation o = pipelines->instrument();
  REQUIRE(o.state == fusion::TrackState::Tracking);
  CHECK(o.method == "features");  // the estimator predicts 1.3 m, below the oscilloscope's lambda
  CHECK((o.T_cam_target.translation() - T_cam_osc.translation()).norm() < 0.03);
  CHECK(angle_between(o.T_cam_target, T_cam_osc) < 2.0 * kDeg);

  // Above the platform, looking down with the bottom camera.
  const Eigen::Vector3d above = lab_geometry().platform.T_world_object.translation() + Eigen::Vector3d(0.08, -0.05, 0.9);
  pipelines->reset(make_pose(above, 0.0), 1.0);
  const Eigen::Isometry3d T_cam_platform =
      (make_pose(above, 0.0) * T_body_cam_bottom()).inverse() * lab_geometry().platform.T_world_object;
  const PanelScene pad{lab_geometry().platform, PinholeCamera::ardrone2_bottom()};
  focus.instrument_id.clear();
  focus.platform = true;
  pipelines->set_focus(focus);
  pipelines->on_video(bgr_frame(pad.view(T_cam_platform), 1.1, CameraId::Bottom));
  const fusion::TargetObservation p = pipelines->platform();
  REQUIRE(p.state == fusion::TrackState::Tracking);
  CHECK((p.T_cam_target.translation() - T_cam_platform.translation()).norm() < 0.03);
  CHECK(angle_between(p.T_cam_target, T_cam_platform) < 2.0 * kDeg);
  // SLAM sees nothing while the bottom camera streams.
  CHECK(pipelines->slam().state == fusion::SlamState::Off);
}

TEST_CASE("vision front-ends: SLAM on front frames gives the camera's trajectory up to a similarity") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const bench::SyntheticRoom room(camera);
  slam::SlamSettings settings;
  settings.mapping_mode = slam::MappingMode::Synchronous;
  fusion::SlamSystemFrontEnd fe(std::make_unique<slam::SlamSystem>(camera, settings));
  const bench::Flight flight = bench::approach_flight(room.panel_center());
  std::vector<bench::PosePair> tracked;
  bool initializing_seen = false;
  for (std::size_t i = 0; i < flight.frames.size() && flight.frames[i].t < 6.0; ++i) {
    const auto& f = flight.frames[i];
    const fusion::SlamFrame& s = fe.process(room.render(f.T_world_cam, static_cast<unsigned>(i)), f.t, std::nullopt);
    initializing_seen = initializing_seen || s.summary.state == fusion::SlamState::Initializing;
    CHECK(s.has_pose == (s.summary.state == fusion::SlamState::Good || s.summary.state == fusion::SlamState::Dodgy));
    if (s.has_pose) tracked.push_back({f.t, s.T_map_cam, f.T_world_cam});
  }
  CHECK(initializing_seen);
  REQUIRE(tracked.size() > 60);
  const auto errors = bench::trajectory_errors(tracked);
  REQUIRE(errors);
  INFO("ATE " << errors->ate_rmse_m * 100 << " cm over " << errors->poses << " poses");
  CHECK(errors->ate_rmse_m < 0.05);
  CHECK(fe.process(room.render(flight.frames[200].T_world_cam, 999), 6.5, std::nullopt).summary.keyframes >= 2);

  const fusion::SlamFrame& paused = fe.pause();
  CHECK(paused.summary.state == fusion::SlamState::Off);
  CHECK_FALSE(paused.has_pose);
  CHECK(paused.map_id == 1);
  fe.restart_map();
  const fusion::SlamFrame& again = fe.process(room.render(flight.frames[0].T_world_cam, 1000), 7.0, std::nullopt);
  CHECK(again.map_id == 2);
  CHECK(again.summary.state == fusion::SlamState::Initializing);
}

namespace {
// The front camera without distortion, like the face tests: the textured head renderer and the
// estimator share it.
PinholeCamera undistorted_front() { return PinholeCamera::ardrone2_front().without_distortion(); }

Eigen::Isometry3d head_at(double yaw_deg, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = face::head_rotation({yaw_deg * kDeg, 0.0, 0.0});
  T.translation() = t;
  return T;
}
}  // namespace

TEST_CASE("vision front-ends: the teacher's face gives a pose with z into the face and 68 landmarks") {
  const face::FaceConfig config = face::default_face_config();
  const Candide3Model candide = Candide3Model::load(config.model);
  auto estimator = std::make_unique<face::FacePoseEstimator>(config, undistorted_front());
  const cv::Mat photo = cv::imread((labo::source_root() / "assets" / "astronaut.png").string(), cv::IMREAD_GRAYSCALE);
  REQUIRE_FALSE(photo.empty());  // run scripts/setup.sh
  face::TexturedHead head = face::texture_head_from_photo(*estimator, candide, photo, 0.063);
  estimator->set_person({"astronaut", 0.063, head.shape_params, 0, {}}, false);
  face::TexturedHeadRenderer renderer(candide, head, undistorted_front());
  fusion::FaceFrontEnd fe(std::move(estimator));

  const Eigen::Isometry3d T_cam_face = head_at(15, {0.04, -0.02, 1.0});
  const fusion::TargetObservation* o = nullptr;
  for (int i = 0; i < 4; ++i) {
    cv::Mat img(360, 640, CV_8UC1, cv::Scalar(120));
    renderer.render(T_cam_face, img);
    o = &fe.process(img, i / 30.0, std::nullopt);
  }
  REQUIRE(o->state == fusion::TrackState::Tracking);
  CHECK(o->image_points.size() == 68);
  // face/ has z out of the face; control's targets have z into it.
  const Eigen::Isometry3d expected = T_cam_face * fusion::flip_about_y();
  CHECK((o->T_cam_target.translation() - expected.translation()).norm() < 0.05);
  CHECK(angle_between(o->T_cam_target, expected) < 5.0 * kDeg);
  CHECK(o->T_cam_target.linear().col(2).z() > 0.8);  // looking at the camera: z points away from it

  cv::Mat empty(360, 640, CV_8UC1, cv::Scalar(120));
  const fusion::TargetObservation& lost = fe.process(empty, 1.0, std::nullopt);
  CHECK(lost.state == fusion::TrackState::Lost);
  CHECK_FALSE(lost.reason.empty());
}

TEST_CASE("vision front-ends: vision prepared, run and applied in steps gives what on_video gives, and the focus may change meanwhile") {
  fusion::FrontEndSettings settings;
  settings.with_face = false;
  settings.slam.mapping_mode = slam::MappingMode::Synchronous;
  const auto inline_run = fusion::make_lab_pipelines(lab_geometry(), ardrone2_cameras(), VisionThresholds{}, estimation::EstimatorConfig{}, settings);
  const auto stepped = fusion::make_lab_pipelines(lab_geometry(), ardrone2_cameras(), VisionThresholds{}, estimation::EstimatorConfig{}, settings);
  const fusion::PlanarTarget& osc = *lab_geometry().find_instrument("oscilloscope");
  const Eigen::Vector3d body = osc.T_world_object.translation() - Eigen::Vector3d(1.5, 0.05, 0.0);
  const PanelScene panel{osc, PinholeCamera::ardrone2_front()};
  fusion::PerceptionFocus focus;
  focus.instrument_id = "oscilloscope";
  focus.feedback = fusion::FeedbackSource::Homography;
  for (fusion::LabPipelines* p : {inline_run.get(), stepped.get()}) {
    p->reset(make_pose(body, 0.0), 0.0);
    p->set_focus(focus);
  }
  fusion::VisionJob job;
  fusion::VisionResults results;
  for (int i = 0; i < 6; ++i) {
    const Seconds t = 0.1 + 0.033 * i;
    const Eigen::Vector3d at = body + Eigen::Vector3d(0.01 * i, 0.0, 0.0);
    const VideoFrame frame = bgr_frame(panel.view(front_camera_at(at, 0.0).inverse() * osc.T_world_object), t, CameraId::Front);
    inline_run->on_video(frame);
    REQUIRE(stepped->prepare_vision(frame, job));
    CHECK(job.instrument_id == "oscilloscope");
    CHECK(job.slam != nullptr);
    fusion::run_vision_job(job, results);
    if (i == 5) {
      // The mission moved on before the worker finished: the result still counts for the instrument
      // it was prepared for.
      fusion::PerceptionFocus other = focus;
      other.instrument_id.clear();
      stepped->set_focus(other);
    }
    stepped->apply_vision(results);
  }
  const fusion::TargetObservation a = inline_run->instrument(), b = stepped->instrument();
  REQUIRE(a.state == fusion::TrackState::Tracking);
  CHECK(b.state == a.state);
  CHECK(b.method == a.method);
  CHECK((b.T_cam_target.translation() - a.T_cam_target.translation()).norm() < 1e-9);
  CHECK(b.placed_in_world == a.placed_in_world);
  const fusion::PoseEstimate pa = inline_run->predict(0.4), pb = stepped->predict(0.4);
  CHECK((pa.T_world_body.translation() - pb.T_world_body.translation()).norm() < 1e-9);
  CHECK(stepped->slam().state == inline_run->slam().state);

  // A frame nothing is asked of needs no job.
  fusion::PerceptionFocus nothing;
  nothing.slam = false;
  stepped->set_focus(nothing);
  CHECK_FALSE(stepped->prepare_vision(bgr_frame(panel.view(front_camera_at(body, 0.0).inverse() * osc.T_world_object), 1.0,
                                                CameraId::Front),
                                      job));
  // Nor does a frame that is no camera image.
  stepped->set_focus(focus);
  VideoFrame odd = bgr_frame(panel.view(front_camera_at(body, 0.0).inverse() * osc.T_world_object), 1.1, CameraId::Front);
  odd.bgr = cv::Mat(360, 640, CV_32FC1, cv::Scalar(0.5));
  CHECK_FALSE(stepped->prepare_vision(odd, job));
}

TEST_CASE("vision front-ends: the platform's offset from the body is levelled by the attitude the frame was taken at") {
  fusion::FrontEndSettings settings;
  settings.with_face = false;
  const auto pipelines = fusion::make_lab_pipelines(lab_geometry(), ardrone2_cameras(), VisionThresholds{}, estimation::EstimatorConfig{}, settings);
  const Eigen::Vector3d platform = lab_geometry().platform.T_world_object.translation();
  const Eigen::Vector3d body = platform + Eigen::Vector3d(0.06, -0.04, 0.9);
  const double roll = 2.0 * kDeg, pitch = -1.5 * kDeg;
  const Eigen::Isometry3d T_world_body = make_pose(body, 0.0, pitch, roll);
  pipelines->reset(make_pose(body, 0.0), 0.0);
  fusion::PerceptionFocus focus;
  focus.slam = false;
  focus.platform = true;
  pipelines->set_focus(focus);
  const PanelScene pad{lab_geometry().platform, PinholeCamera::ardrone2_bottom()};
  const Eigen::Isometry3d T_cam_platform = (T_world_body * T_body_cam_bottom()).inverse() * lab_geometry().platform.T_world_object;
  const Eigen::Vector3d truth = platform - body;  // heading frame = world frame at yaw 0

  SECTION("without navdata the attitude at the frame is unknown: no offset") {
    pipelines->on_video(bgr_frame(pad.view(T_cam_platform), 0.2, CameraId::Bottom));
    REQUIRE(pipelines->platform().state == fusion::TrackState::Tracking);
    CHECK_FALSE(pipelines->platform().offset_heading_m);
  }
  SECTION("tilted when the frame was taken, level since: the frame's attitude levels it") {
    NavdataSample n;
    n.altitude_m = 0.9;
    for (int i = 0; i <= 60; ++i) {
      n.t = 0.005 * i;
      n.sequence = static_cast<std::uint32_t>(i + 1);
      const bool before_capture = n.t - 0.04 < 0.2 - 0.075 + 0.02;  // navdata and video delays of the defaults
      n.roll_rad = before_capture ? roll : 0.0;
      n.pitch_rad = before_capture ? pitch : 0.0;
      pipelines->on_navdata(n);
    }
    pipelines->on_video(bgr_frame(pad.view(T_cam_platform), 0.2, CameraId::Bottom));
    const fusion::TargetObservation p = pipelines->platform();
    REQUIRE(p.state == fusion::TrackState::Tracking);
    REQUIRE(p.offset_heading_m);
    CHECK((*p.offset_heading_m - truth).head<2>().norm() < 0.015);
    CHECK(p.offset_heading_m->z() == Approx(truth.z()).margin(0.03));
    // Levelled by the latest (level) attitude instead, the 2.5 degrees would put it ~4 cm off.
    const Eigen::Vector3d unlevelled = (T_body_cam_bottom() * p.T_cam_target).translation();
    CHECK((unlevelled - truth).head<2>().norm() > 0.03);
  }
}
