#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "core/frames.hpp"
#include "localization/face/head_tracker.hpp"
#include "localization/fusion/face_front_end.hpp"
#include "teacher_scene.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::face;
using labo::face::testing::TeacherScene;

namespace {

constexpr double kFps = 30.0;

Eigen::Vector3d head_centre(const Eigen::Isometry3d& T_cam_face, const HeadTrackerOptions& o) {
  return T_cam_face * Eigen::Vector3d(0, 0, -o.centre_behind_face_m);
}

// The camera 1.1 m in front of a teacher standing at `at`, at eye height, looking at them (+x); the
// tracker taught on them facing it at t = 0.
HeadTracker taught_facing(TeacherScene& t, const Eigen::Vector2d& at) {
  t.camera_at = Eigen::Vector3d(at.x() - 1.1, at.y(), t.lab.teacher.eye_height_m);
  HeadTracker tracker(t.renderer.camera(CameraId::Front));
  const SceneState facing = t.scene(at, std::numbers::pi);
  tracker.learn(t.gray(facing), t.T_cam_face(facing), 0.0);
  return tracker;
}

}  // namespace

TEST_CASE("head tracker: a teacher who turns their back and walks on is followed by the head") {
  TeacherScene t;
  const Eigen::Vector2d start = t.lab.teacher.waypoints.front();
  // The drone 1.1 m in front of the teacher's face, at eye height, looking at them (+x).
  t.camera_at = Eigen::Vector3d(start.x() - 1.1, start.y(), t.lab.teacher.eye_height_m);
  HeadTracker tracker(t.renderer.camera(CameraId::Front));
  const SceneState first = t.scene(start, std::numbers::pi);  // facing the drone (-x)
  tracker.learn(t.gray(first), t.T_cam_face(first), 0.0);
  REQUIRE(tracker.active());

  // Over 3 s the teacher turns round (60 deg/s) and walks 0.5 m to the side and 0.3 m away.
  double worst_m = 0, worst_distance = 0;
  for (int i = 1; i <= 90; ++i) {
    const double s = i / 90.0;
    const Eigen::Vector2d at = start + Eigen::Vector2d(0.3 * s, 0.5 * s);
    const SceneState scene = t.scene(at, std::numbers::pi + std::numbers::pi * s);
    const auto head = tracker.follow(t.gray(scene), i / kFps);
    INFO("frame " << i << ", turned " << 180 * s << " deg");
    REQUIRE(head.has_value());
    const Eigen::Vector3d truth = head_centre(t.T_cam_face(scene), tracker.options());
    worst_m = std::max(worst_m, (head->p_cam_head_m - truth).norm());
    worst_distance = std::max(worst_distance, std::abs(head->p_cam_head_m.norm() / truth.norm() - 1.0));
    CHECK(head->since_face_s == Approx(i / kFps));
  }
  INFO("worst position error " << worst_m << " m, worst distance error " << 100 * worst_distance << " %");
  CHECK(worst_m < 0.15);
  CHECK(worst_distance < 0.12);
}

TEST_CASE("head tracker: a head that leaves or is followed beyond its time is lost, and bad frames are refused") {
  TeacherScene t;
  const Eigen::Vector2d start = t.lab.teacher.waypoints.front();
  t.camera_at = Eigen::Vector3d(start.x() - 1.1, start.y(), t.lab.teacher.eye_height_m);
  HeadTrackerOptions options;
  options.max_follow_s = 1.0;
  HeadTracker tracker(t.renderer.camera(CameraId::Front), options);
  CHECK_FALSE(tracker.follow(t.gray(t.scene(start, std::numbers::pi)), 0.0).has_value());  // nothing learnt
  CHECK(tracker.lost_reason() == HeadLostReason::NotLearnt);

  const SceneState facing = t.scene(start, std::numbers::pi);
  const cv::Mat still = t.gray(facing);
  tracker.learn(still, t.T_cam_face(facing), 0.0);
  CHECK_FALSE(tracker.follow(cv::Mat(), 0.1).has_value());
  CHECK_FALSE(tracker.follow(cv::Mat(360, 640, CV_8UC3, cv::Scalar::all(0)), 0.1).has_value());
  CHECK(tracker.active());  // bad frames leave the track as it was
  CHECK(tracker.lost_reason() == HeadLostReason::None);
  CHECK(tracker.follow(still, 0.5).has_value());
  CHECK_FALSE(tracker.follow(still, 1.1).has_value());  // 1.1 s after the last face
  CHECK_FALSE(tracker.active());
  CHECK(tracker.lost_reason() == HeadLostReason::FaceTooLongAgo);

  // The teacher gone from the view: no head is made up on the wall behind.
  tracker.learn(still, t.T_cam_face(facing), 2.0);
  SceneState gone = facing;
  gone.teacher_present = false;
  const cv::Mat empty = t.gray(gone);
  bool lost = false;
  for (int i = 1; i <= 10 && !lost; ++i) lost = !tracker.follow(empty, 2.0 + i / kFps).has_value();
  CHECK(lost);
  CHECK(tracker.lost_reason() == HeadLostReason::NoMatch);
  // ... nor later, while its template is kept to find it again.
  int made_up = 0;
  for (int i = 11; i <= 70; ++i) made_up += tracker.follow(empty, 2.0 + i / kFps).has_value();
  CHECK(made_up == 0);
  tracker.reset();
  CHECK(tracker.lost_reason() == HeadLostReason::NotLearnt);
}

TEST_CASE("face front-end: with head tracking, a face turned away is reported as the head's place only, then lost") {
  TeacherScene t;
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  t.camera_at = Eigen::Vector3d(at.x() - 1.1, at.y(), t.lab.teacher.eye_height_m);
  const FaceConfig config = default_face_config();  // head tracking on
  fusion::FaceFrontEnd front_end(std::make_unique<FacePoseEstimator>(config, t.renderer.camera(CameraId::Front)));
  const SceneState facing = t.scene(at, std::numbers::pi);
  const cv::Mat face_on = t.gray(facing);
  Seconds now = 0;
  for (int i = 0; i < 5 && front_end.last_result().state != FaceState::Tracking; ++i, now += 1 / kFps) {
    front_end.process(face_on, now, std::nullopt);
  }
  REQUIRE(front_end.last_result().tracking());
  const Eigen::Isometry3d posed = front_end.process(face_on, now, std::nullopt).T_cam_target;
  CHECK_FALSE(front_end.process(face_on, now += 1 / kFps, std::nullopt).position_only);

  // Turned round over 1.5 s: the face is lost, the head is not.
  fusion::TargetObservation last;
  Eigen::Matrix3d last_posed = posed.linear();
  for (int i = 1; i <= 45; ++i) {
    const SceneState s = t.scene(at, std::numbers::pi * (1 + i / 45.0));
    last = front_end.process(t.gray(s), now += 1 / kFps, std::nullopt);
    if (!last.position_only) last_posed = last.T_cam_target.linear();
  }
  CHECK_FALSE(front_end.last_result().tracking());
  REQUIRE(last.state == fusion::TrackState::Tracking);
  CHECK(last.position_only);
  CHECK(last.method == "head");
  CHECK(last.image_points.size() == 4);
  // The teacher stood still: the head's centre, 0.09 m behind the face posed at the start.
  CHECK((last.T_cam_target.translation() - posed.translation()).norm() < 0.2);
  CHECK(last.T_cam_target.linear().isApprox(last_posed));  // the last posed face's rotation

  // The video link drops for 0.6 s: the head is found again on the first frame after, not searched for.
  const fusion::TargetObservation after_gap = front_end.process(t.gray(t.scene(at, 2 * std::numbers::pi)), now += 0.6, std::nullopt);
  CHECK(after_gap.state == fusion::TrackState::Tracking);
  CHECK(after_gap.position_only);
  INFO("after the gap " << after_gap.T_cam_target.translation().transpose() << ", before " << last.T_cam_target.translation().transpose() << ", score " << after_gap.quality);
  CHECK((after_gap.T_cam_target.translation() - last.T_cam_target.translation()).norm() < 0.1);

  // Turned away for longer than the head is followed: lost, with the face's reason.
  const cv::Mat back = t.gray(t.scene(at, 0.0));
  for (int i = 0; i < 21 * kFps; ++i) last = front_end.process(back, now += 1 / kFps, std::nullopt);
  CHECK(last.state == fusion::TrackState::Lost);
  CHECK_FALSE(last.position_only);
  CHECK(last.reason == to_string(HeadLostReason::FaceTooLongAgo));  // not the face's "no face found"
}

TEST_CASE("face front-end: without head tracking, a face turned away is lost") {
  TeacherScene t;
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  t.camera_at = Eigen::Vector3d(at.x() - 1.1, at.y(), t.lab.teacher.eye_height_m);
  FaceConfig config = default_face_config();
  config.head_tracking = false;
  fusion::FaceFrontEnd front_end(std::make_unique<FacePoseEstimator>(config, t.renderer.camera(CameraId::Front)));
  const cv::Mat face_on = t.gray(t.scene(at, std::numbers::pi));
  Seconds now = 0;
  for (int i = 0; i < 5 && !front_end.last_result().tracking(); ++i, now += 1 / kFps) front_end.process(face_on, now, std::nullopt);
  REQUIRE(front_end.last_result().tracking());
  // Turned away at once. The tracked landmarks may lock onto the hair for a frame or so (a face-like
  // fit at 2 px RMS) until the detector's next check refuses it; within a second the face is lost,
  // and never is a head reported in its place.
  const cv::Mat back_image = t.gray(t.scene(at, 0.0));
  fusion::TargetObservation back;
  for (int i = 0; i < kFps && back.state != fusion::TrackState::Lost; ++i) {
    back = front_end.process(back_image, now += 1 / kFps, std::nullopt);
    CHECK_FALSE(back.position_only);
  }
  CHECK(back.state == fusion::TrackState::Lost);
  CHECK_FALSE(front_end.last_head().has_value());
}

TEST_CASE("head tracker: a head lost from the view is found again round where it was while its template is kept") {
  TeacherScene t;
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  HeadTracker tracker = taught_facing(t, at);
  Seconds now = 0;
  // Turned away over 2 s, followed by the head.
  for (int i = 1; i <= 60; ++i) REQUIRE(tracker.follow(t.gray(t.scene(at, std::numbers::pi * (1 + i / 60.0))), now += 1 / kFps));
  // Out of the view for a second (the drone turned away, or someone passed between): lost.
  SceneState gone = t.scene(at, 0.0);
  gone.teacher_present = false;
  const cv::Mat empty = t.gray(gone);
  for (int i = 0; i < 30; ++i) tracker.follow(empty, now += 1 / kFps);
  REQUIRE_FALSE(tracker.active());
  const HeadLostReason why = tracker.lost_reason();
  CHECK(why == HeadLostReason::NoMatch);

  SECTION("back in the view 0.3 m to the side: found again at once, at its distance") {
    const Eigen::Vector2d moved = at + Eigen::Vector2d(0.1, 0.3);
    const SceneState back = t.scene(moved, 0.0);
    std::optional<HeadObservation> head;
    int frames = 0;
    for (; frames < 5 && !head; ++frames) head = tracker.follow(t.gray(back), now += 1 / kFps);
    REQUIRE(head.has_value());
    CHECK(frames == 1);
    CHECK(head->reacquired);
    const Eigen::Vector3d truth = head_centre(t.T_cam_face(back), tracker.options());
    INFO("found at " << head->p_cam_head_m.transpose() << ", truth " << truth.transpose());
    CHECK((head->p_cam_head_m - truth).norm() < 0.2);
    // ... and followed on from there.
    const auto next = tracker.follow(t.gray(back), now += 1 / kFps);
    REQUIRE(next.has_value());
    CHECK_FALSE(next->reacquired);
    CHECK(tracker.lost_reason() == HeadLostReason::None);
  }
  SECTION("back after the reacquisition time: not found, the loss stands") {
    now += tracker.options().reacquire_s;
    CHECK_FALSE(tracker.follow(t.gray(t.scene(at, 0.0)), now).has_value());
    CHECK(tracker.lost_reason() == why);
  }
}

TEST_CASE("head tracker: video that drops right after a posed face: the head is looked for with that face's look") {
  TeacherScene t;
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  HeadTracker tracker = taught_facing(t, at);
  // No frame followed the posed one: its template was still to be made when the video dropped.
  tracker.interrupt(0.6);
  REQUIRE_FALSE(tracker.active());
  CHECK(tracker.lost_reason() == HeadLostReason::FrameGap);
  // Back 0.15 m aside, turned a little.
  const SceneState back = t.scene(at + Eigen::Vector2d(0.0, 0.15), std::numbers::pi * 1.05);
  const auto head = tracker.follow(t.gray(back), 0.6 + 1 / kFps);
  REQUIRE(head.has_value());
  CHECK(head->reacquired);
  const Eigen::Vector3d truth = head_centre(t.T_cam_face(back), tracker.options());
  INFO("found at " << head->p_cam_head_m.transpose() << ", truth " << truth.transpose());
  CHECK((head->p_cam_head_m - truth).norm() < 0.15);
}

TEST_CASE("head tracker: a head approached fast keeps its distance") {
  TeacherScene t;
  const Eigen::Vector2d at = t.lab.teacher.waypoints.front();
  // At the face's height, and over the head as face-follow watches a head without its face.
  const double over_m = GENERATE(0.0, 0.3);
  const double speed = GENERATE(0.6, 1.0);
  const double z = t.lab.teacher.eye_height_m + over_m;
  const auto place_camera = [&](double range_m) { t.camera_at = Eigen::Vector3d(at.x() - range_m, at.y(), z); };
  const double from_m = 2.2, to_m = over_m > 0 ? 1.0 : 0.7;
  place_camera(from_m);
  HeadTracker tracker(t.renderer.camera(CameraId::Front));
  const SceneState facing = t.scene(at, std::numbers::pi);
  tracker.learn(t.gray(facing), t.T_cam_face(facing), 0.0);
  // The teacher turns away in 3 s (as in the first test) while the drone flies at them.
  const int frames = static_cast<int>((from_m - to_m) / speed * kFps);
  double worst = 0;
  for (int i = 1; i <= frames; ++i) {
    place_camera(from_m - speed * i / kFps);
    const SceneState s = t.scene(at, std::numbers::pi * (1 + std::min(1.0, i / (3.0 * kFps))));
    const auto head = tracker.follow(t.gray(s), i / kFps);
    INFO("over " << over_m << " m, " << speed << " m/s, frame " << i << ": " << to_string(tracker.lost_reason()));
    REQUIRE(head.has_value());
    const Eigen::Vector3d truth = head_centre(t.T_cam_face(s), tracker.options());
    worst = std::max(worst, std::abs(head->p_cam_head_m.norm() / truth.norm() - 1.0));
  }
  // Measured 7-11 % at the face's height, 7 % over the head at 1.0 m/s and 19 % at 0.6 m/s: the
  // adapting template takes on the scale the box has and the box's size lags (docs/face.md).
  INFO("over " << over_m << " m, " << speed << " m/s: worst distance error " << 100 * worst << " %");
  CHECK(worst < 0.2);
}
