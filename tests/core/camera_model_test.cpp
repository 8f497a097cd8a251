#include <catch2/catch.hpp>
#include <opencv2/calib3d.hpp>
#include <random>

#include "core/camera_model.hpp"

using namespace labo;

TEST_CASE("camera: projection and unprojection round trip through the AR.Drone's distortion") {
  const PinholeCamera cam = PinholeCamera::ardrone2_front();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(40, 600), uy(30, 330), depth(0.3, 8.0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d px(ux(rng), uy(rng));
    const Eigen::Vector3d ray = cam.unproject(px);
    CHECK(ray.norm() == Approx(1.0));
    const auto back = cam.project(ray * depth(rng));
    REQUIRE(back);
    CHECK((*back - px).norm() < 1e-6);
  }
}

TEST_CASE("camera: projection agrees with OpenCV's projectPoints") {
  const PinholeCamera cam = PinholeCamera::ardrone2_front();
  std::vector<cv::Point3d> pts{{0.1, -0.2, 2.0}, {-0.5, 0.3, 3.0}, {0.0, 0.0, 1.0}, {0.4, 0.1, 1.5}};
  std::vector<cv::Point2d> cv_px;
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam.K(), cam.distortion_coefficients(), cv_px);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto px = cam.project({pts[i].x, pts[i].y, pts[i].z});
    REQUIRE(px);
    CHECK(px->x() == Approx(cv_px[i].x).margin(1e-9));
    CHECK(px->y() == Approx(cv_px[i].y).margin(1e-9));
  }
}

TEST_CASE("camera: points behind the camera do not project") {
  const PinholeCamera cam = PinholeCamera::ardrone2_bottom();
  CHECK_FALSE(cam.project({0, 0, -1}));
  CHECK_FALSE(cam.project({0, 0, 0}));
  const auto centre = cam.project({0, 0, 2});
  REQUIRE(centre);
  CHECK(centre->x() == Approx(319.5));
  CHECK(centre->y() == Approx(218.7));
}

TEST_CASE("camera: invalid intrinsics are refused with the field's name") {
  CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
  k.fx = -1;
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("focal lengths fx, fy must be positive"));
  k = PinholeCamera::ardrone2_front().intrinsics();
  k.width = 0;
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("image size 0x360 must be positive"));
  k = PinholeCamera::ardrone2_front().intrinsics();
  k.cy = std::nan("");
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("must be finite"));
}

TEST_CASE("camera: a scaled camera projects to the scaled pixel") {
  const PinholeCamera cam = PinholeCamera::ardrone2_bottom();
  const PinholeCamera half = cam.scaled(0.5);
  CHECK(half.width() == 320);
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  const auto full = cam.project(p), small = half.project(p);
  REQUIRE(full);
  REQUIRE(small);
  CHECK(small->x() == Approx((full->x() + 0.5) * 0.5 - 0.5));
}
