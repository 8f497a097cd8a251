#include <catch2/catch.hpp>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "render_fixtures.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::test;

namespace {

// A 2x2 checkerboard panel: its centre is an X-corner that cornerSubPix finds to a tenth of a pixel.
std::filesystem::path write_checker(const std::filesystem::path& dir, int w, int h) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(235, 235, 235));
  img(cv::Rect(0, 0, w / 2, h / 2)).setTo(cv::Scalar(20, 20, 20));
  img(cv::Rect(w / 2, h / 2, w - w / 2, h - h / 2)).setTo(cv::Scalar(20, 20, 20));
  const auto path = dir / "checker.png";
  cv::imwrite(path.string(), img);
  return path;
}

}  // namespace

TEST_CASE("render: a known 3D point appears where the camera model projects it, distortion included") {
  LabDescription lab = load_lab_description(default_lab_path());
  InstrumentSpec& scope = lab.instruments.front();
  const ScratchDir scratch("render_checker");
  scope.template_path = write_checker(scratch.path(), 400, 200);
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  const PinholeCamera& camera = renderer.camera(CameraId::Front);
  const Eigen::Vector3d point = scope.T_world_object.translation();  // the X-corner

  int checked = 0;
  // The point straight ahead, then towards each side of the image where the lens distorts most.
  for (const Eigen::Vector3d& look : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0.35, 0), Eigen::Vector3d(0, -0.35, 0),
                                      Eigen::Vector3d(0, 0.3, 0.3), Eigen::Vector3d(0, -0.25, -0.15),
                                      Eigen::Vector3d(0, 0.1, -0.18)}) {
    const Eigen::Vector3d eye = point + Eigen::Vector3d(-1.1, 0.05, 0.02);
    const Eigen::Isometry3d body = body_looking_at(eye, point + look);
    const auto expected = camera.project((body * T_body_cam_front()).inverse() * point);
    REQUIRE(expected);
    REQUIRE(camera.in_image(*expected, 15));
    cv::Mat bgr, gray;
    renderer.render(CameraId::Front, still_scene(body), bgr);
    cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
    std::vector<cv::Point2f> corner{cv::Point2f(static_cast<float>(expected->x() + 3), static_cast<float>(expected->y() - 2))};
    cv::cornerSubPix(gray, corner, cv::Size(6, 6), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    const double error = std::hypot(corner[0].x - expected->x(), corner[0].y - expected->y());
    INFO("looking " << look.transpose() << ": expected " << expected->transpose() << ", found " << corner[0]);
    CHECK(error < 0.5);
    ++checked;
  }
  CHECK(checked == 6);
}

TEST_CASE("render: the bottom camera sees the landing pattern upright on the platform above the base") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  const PinholeCamera& camera = renderer.camera(CameraId::Bottom);
  SceneState s = still_scene(make_pose({0.0, 0.0, 2.0}, 0.0));
  cv::Mat bgr;
  renderer.render(CameraId::Bottom, s, bgr);

  // Where the template should be: the homography from its pixels to the image through the camera.
  const cv::Mat pattern = cv::imread(lab.platform.template_path.string(), cv::IMREAD_COLOR);
  REQUIRE_FALSE(pattern.empty());
  const Eigen::Isometry3d T_cam_world = (s.T_world_body * T_body_cam_bottom()).inverse();
  const auto corners = lab.platform.corners_world();  // top-left, top-right, bottom-right, bottom-left
  std::vector<cv::Point2f> img_pts, tpl_pts{{-0.5f, -0.5f},
                                            {pattern.cols - 0.5f, -0.5f},
                                            {pattern.cols - 0.5f, pattern.rows - 0.5f},
                                            {-0.5f, pattern.rows - 0.5f}};
  for (const auto& c : corners) {
    const auto p = camera.project(T_cam_world * c);
    REQUIRE(p);
    REQUIRE(camera.in_image(*p, 2));
    img_pts.emplace_back(static_cast<float>(p->x()), static_cast<float>(p->y()));
  }
  // The drone faces +x: the pattern's top is at the top of the image.
  CHECK(img_pts[0].y < img_pts[3].y);
  CHECK(img_pts[0].x < img_pts[1].x);
  const cv::Mat H = cv::getPerspectiveTransform(tpl_pts, img_pts);
  cv::Mat rotated;
  cv::rotate(pattern, rotated, cv::ROTATE_180);
  const TemplateMatch upright = compare_with_template(bgr, pattern, H), turned = compare_with_template(bgr, rotated, H);
  INFO("upright: NCC " << upright.ncc << ", mean abs diff " << upright.mean_abs_diff << "; turned: NCC " << turned.ncc
                       << ", mean abs diff " << turned.mean_abs_diff);
  CHECK(upright.ncc > 0.97);
  CHECK(upright.mean_abs_diff < 8);
  CHECK(turned.mean_abs_diff > 2 * upright.mean_abs_diff);
}

TEST_CASE("render: landed on the platform, the bottom camera (below the hull) sees the pattern from 1 cm") {
  const LabDescription lab = load_lab_description(default_lab_path());
  LabRenderer renderer(lab, ardrone_cameras(), std::nullopt, 1, sharp_options());
  cv::Mat bgr, grey;
  renderer.render(CameraId::Bottom, still_scene(lab.T_world_base), bgr);
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  // From 1 cm the pattern's texels are magnified: the image is the pattern's white or black, nothing
  // of the floor's colours.
  const int rect = renderer.rect_at(CameraId::Bottom, lab.T_world_base, 320, 180);
  REQUIRE(rect >= 0);
  CHECK(renderer.scene().rects[static_cast<std::size_t>(rect)].name == lab.platform.id + ".panel");
}
