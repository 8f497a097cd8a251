#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include "render_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::test;

namespace {

// Counts, over a patch of pixels, how many show the texel of rectangle `rect` under them.
int pixels_showing(const cv::Mat& bgr, const LabScene& scene, int rect, const PinholeCamera& camera,
                   const Eigen::Isometry3d& T_world_cam, const Eigen::Vector2d& centre, int half) {
  int n = 0;
  for (int dy = -half; dy <= half; ++dy) {
    for (int dx = -half; dx <= half; ++dx) {
      const int x = static_cast<int>(centre.x()) + dx, y = static_cast<int>(centre.y()) + dy;
      const auto texel = texel_seen(scene, rect, camera, T_world_cam, x, y);
      if (texel && colour_distance(bgr.at<cv::Vec3b>(y, x), *texel) <= 9) ++n;
    }
  }
  return n;
}

}  // namespace

TEST_CASE("render: a bench hides the wall behind it, the wall shows above it") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  const PinholeCamera& camera = renderer.camera(CameraId::Front);
  const Eigen::Isometry3d body = body_looking_at({4.2, -0.5, 1.2}, {6.5, -0.6, 0.8});
  const Eigen::Isometry3d T_world_cam = body * T_body_cam_front();
  cv::Mat bgr;
  renderer.render(CameraId::Front, still_scene(body), bgr);
  const int wall = renderer.scene().find("wall_xmax"), bench = renderer.scene().find("bench_east.xmin");
  REQUIRE(wall >= 0);
  REQUIRE(bench >= 0);

  // A wall point low behind the bench: the bench's front face is seen there, not the wall.
  const auto hidden = camera.project(T_world_cam.inverse() * Eigen::Vector3d(6.5, -0.6, 0.3));
  REQUIRE(hidden);
  REQUIRE(camera.in_image(*hidden, 10));
  CHECK(renderer.rect_at(CameraId::Front, body, static_cast<int>(hidden->x()), static_cast<int>(hidden->y())) == bench);
  const int patch = 5 * 5 * 4 + 4 * 5 + 1;  // 11 x 11
  CHECK(pixels_showing(bgr, renderer.scene(), bench, camera, T_world_cam, *hidden, 5) > patch * 9 / 10);
  CHECK(pixels_showing(bgr, renderer.scene(), wall, camera, T_world_cam, *hidden, 5) < patch / 4);

  // A wall point above the bench and its instruments: the wall.
  const auto above = camera.project(T_world_cam.inverse() * Eigen::Vector3d(6.5, -0.6, 1.2));
  REQUIRE(above);
  REQUIRE(camera.in_image(*above, 10));
  CHECK(renderer.rect_at(CameraId::Front, body, static_cast<int>(above->x()), static_cast<int>(above->y())) == wall);
  CHECK(pixels_showing(bgr, renderer.scene(), wall, camera, T_world_cam, *above, 5) > patch * 9 / 10);
}

TEST_CASE("render: an instrument's panel shows its template in front of the bench and the wall") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  const PinholeCamera& camera = renderer.camera(CameraId::Front);
  const InstrumentSpec& scope = lab.instruments.front();
  const Eigen::Vector3d centre = scope.T_world_object.translation();
  const Eigen::Isometry3d body = body_looking_at(centre + Eigen::Vector3d(-1.0, 0.3, 0.2), centre);
  const Eigen::Isometry3d T_world_cam = body * T_body_cam_front();
  cv::Mat bgr;
  renderer.render(CameraId::Front, still_scene(body), bgr);
  // The template warped where the camera model puts the panel's corners.
  const cv::Mat tpl = cv::imread(scope.template_path.string(), cv::IMREAD_COLOR);
  REQUIRE_FALSE(tpl.empty());
  std::vector<cv::Point2f> tpl_pts{{-0.5f, -0.5f}, {tpl.cols - 0.5f, -0.5f}, {tpl.cols - 0.5f, tpl.rows - 0.5f}, {-0.5f, tpl.rows - 0.5f}};
  std::vector<cv::Point2f> img_pts;
  for (const auto& c : scope.corners_world()) {
    const auto p = camera.project(T_world_cam.inverse() * c);
    REQUIRE(p);
    img_pts.emplace_back(static_cast<float>(p->x()), static_cast<float>(p->y()));
  }
  const TemplateMatch m = compare_with_template(bgr, tpl, cv::getPerspectiveTransform(tpl_pts, img_pts));
  INFO("NCC " << m.ncc << ", mean abs diff " << m.mean_abs_diff);
  CHECK(m.ncc > 0.9);
  CHECK(m.mean_abs_diff < 12);
}

TEST_CASE("render: the teacher stands in front of the wall and hides it") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  const PinholeCamera& camera = renderer.camera(CameraId::Front);
  const Eigen::Vector2d at = lab.teacher.waypoints.front();
  const Eigen::Isometry3d body = body_looking_at({at.x() - 1.8, at.y(), 1.4}, {at.x(), at.y(), 1.3});
  const Eigen::Isometry3d T_world_cam = body * T_body_cam_front();
  SceneState s = still_scene(body);
  place_teacher(s, lab, at.x(), at.y(), std::numbers::pi);  // facing the drone
  const auto chest = camera.project(T_world_cam.inverse() * Eigen::Vector3d(at.x() - lab.teacher.body_radius_m, at.y(), 1.2));
  REQUIRE(chest);
  cv::Mat with, without;
  renderer.render(CameraId::Front, s, with);
  CHECK(renderer.last_stats(CameraId::Front).teacher_drawn);
  s.teacher_present = false;
  renderer.render(CameraId::Front, s, without);
  CHECK_FALSE(renderer.last_stats(CameraId::Front).teacher_drawn);
  // The shirt is blue; nothing of the lab behind is.
  const cv::Vec3b shirt = with.at<cv::Vec3b>(static_cast<int>(chest->y()), static_cast<int>(chest->x()));
  const cv::Vec3b behind = without.at<cv::Vec3b>(static_cast<int>(chest->y()), static_cast<int>(chest->x()));
  INFO("shirt " << shirt << ", behind " << behind);
  CHECK(shirt[0] > 1.5 * shirt[2]);
  CHECK(cv::norm(shirt, behind, cv::NORM_L1) > 60);
  // The head is above the body, in front of the wall: the image differs there too.
  const auto face = camera.project(T_world_cam.inverse() * s.T_world_head.translation());
  REQUIRE(face);
  const cv::Rect box(static_cast<int>(face->x()) - 8, static_cast<int>(face->y()) - 8, 17, 17);
  REQUIRE((box & cv::Rect(0, 0, with.cols, with.rows)) == box);
  CHECK(cv::norm(with(box), without(box), cv::NORM_L1) > 17 * 17 * 30);
}
