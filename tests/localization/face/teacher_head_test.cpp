#include <catch2/catch.hpp>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "core/frames.hpp"
#include "drone/sim/lab_renderer.hpp"
#include "localization/face/face_pose_estimator.hpp"
#include "localization/face/teacher_head.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::face;
using Catch::Matchers::Contains;

namespace {

// The teacher at `at`, facing yaw; the drone's front camera 1 m in front of their eyes, looking at them.
struct TeacherShot {
  SceneState scene;
  Eigen::Isometry3d T_cam_face;
};

TeacherShot shot(const LabDescription& lab, const Eigen::Vector2d& at, double yaw, double distance_m) {
  TeacherShot s;
  const Eigen::Vector3d f(std::cos(yaw), std::sin(yaw), 0.0), up = Eigen::Vector3d::UnitZ();
  s.scene.teacher_floor_xy = at;
  s.scene.T_world_head.linear().col(0) = up.cross(f);
  s.scene.T_world_head.linear().col(1) = up;
  s.scene.T_world_head.linear().col(2) = f;
  s.scene.T_world_head.translation() = Eigen::Vector3d(at.x(), at.y(), lab.teacher.eye_height_m);
  const Eigen::Vector3d eye = s.scene.T_world_head.translation() + distance_m * f;
  s.scene.T_world_body = make_pose(eye + f * T_body_cam_front().translation().x(), std::atan2(-f.y(), -f.x()));
  s.T_cam_face = (s.scene.T_world_body * T_body_cam_front()).inverse() * s.scene.T_world_head;
  return s;
}

}  // namespace

TEST_CASE("teacher head: the rendered teacher's face is found by dlib and its pose estimated") {
  const LabDescription lab = load_lab_description(default_lab_path());
  const TexturedHeadModel head = load_lab_teacher_head(lab);
  CHECK(head.vertices_face_m.size() == 113);
  CHECK(head.texture_bgr.type() == CV_8UC3);
  LabRenderOptions sharp;
  sharp.motion_blur = false;
  sharp.noise = false;
  const CamerasConfig cameras = ardrone2_cameras();
  LabRenderer renderer(lab, cameras, head, 1, sharp);
  FacePoseEstimator estimator(default_face_config(), renderer.camera(CameraId::Front));

  const TeacherShot s = shot(lab, lab.teacher.waypoints.front(), 0.3, 1.0);
  cv::Mat bgr, gray;
  renderer.render(CameraId::Front, s.scene, bgr);
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  // While lost, the detector cycles through its search scales frame by frame.
  FaceResult r = estimator.process(gray, 0.0);
  for (int i = 1; i < 3 && !r.tracking(); ++i) r = estimator.process(gray, i / 30.0);
  INFO("face state: " << to_string(r.state) << ", " << to_string(r.reason) << ", faces found " << r.faces_found);
  REQUIRE(r.tracking());
  const double error_m = (r.T_cam_face.translation() - s.T_cam_face.translation()).norm();
  const double angle_deg =
      Eigen::AngleAxisd(r.T_cam_face.linear().transpose() * s.T_cam_face.linear()).angle() * 180 / std::numbers::pi;
  INFO("position error " << error_m << " m, rotation error " << angle_deg << " deg");
  CHECK(error_m < 0.08);
  CHECK(angle_deg < 10);

  // From behind, there is no face.
  TeacherShot back = s;
  back.scene.T_world_head.linear() = back.scene.T_world_head.linear() * Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY());
  renderer.render(CameraId::Front, back.scene, bgr);
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  FacePoseEstimator fresh(default_face_config(), renderer.camera(CameraId::Front));
  for (int i = 0; i < 3; ++i) CHECK_FALSE(fresh.process(gray, i / 30.0).tracking());
}

TEST_CASE("teacher head: a missing photograph or an implausible eye distance is refused") {
  CHECK_THROWS_WITH(load_teacher_head("/nonexistent/face.png", 0.063), Contains("/nonexistent/face.png") && Contains("no such file"));
  CHECK_THROWS_WITH(load_teacher_head("/nonexistent/face.png", 0.2), Contains("interpupillary"));
}
