#include <catch2/catch.hpp>

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/planar/pose/area_pose_refiner.hpp"
#include "localization/planar/pose/planar_pose.hpp"
#include "bench/planar/synthetic_scene.hpp"
#include "tests/localization/planar/supersampled_pixel.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

constexpr double kW = 0.40, kH = 0.30, kDeg = 3.14159265358979 / 180.0;

// A frame as a camera forms it: each raw pixel the mean of 8 x 8 sub-pixel rays through the lens
// (distortion included) onto the panel (nearest texel of the template; grey 90 around it).
cv::Mat integrated_view(const PinholeCamera& camera, const cv::Mat& panel, const Eigen::Isometry3d& T_cam_object) {
  cv::Mat frame(camera.height(), camera.width(), CV_8UC1, cv::Scalar(90));
  const Eigen::Isometry3d T_object_cam = T_cam_object.inverse();
  // Only around the panel: its raw bounding box plus a margin.
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (int k = 0; k <= 40; ++k) {
    const double f = k / 40.0;
    for (const Eigen::Vector2d& s : {Eigen::Vector2d(f, 0), Eigen::Vector2d(f, 1), Eigen::Vector2d(0, f), Eigen::Vector2d(1, f)}) {
      const auto p = camera.project(T_cam_object * Eigen::Vector3d((s.x() - 0.5) * kW, (s.y() - 0.5) * kH, 0));
      REQUIRE(p);
      x0 = std::min(x0, p->x()), x1 = std::max(x1, p->x()), y0 = std::min(y0, p->y()), y1 = std::max(y1, p->y());
    }
  }
  const int left = std::max(0, static_cast<int>(x0) - 4), right = std::min(camera.width() - 1, static_cast<int>(x1) + 4);
  const int top = std::max(0, static_cast<int>(y0) - 4), bottom = std::min(camera.height() - 1, static_cast<int>(y1) + 4);
  for (int y = top; y <= bottom; ++y) {
    for (int x = left; x <= right; ++x) {
      frame.at<uchar>(y, x) = cv::saturate_cast<uchar>(supersampled_pixel(camera, panel, kW, kH, T_object_cam, x, y, 8, 90.0));
    }
  }
  return frame;
}

Eigen::Isometry3d tilted(const Eigen::Isometry3d& T, double about_y_rad, double about_x_rad) {
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = (Eigen::AngleAxisd(about_y_rad, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(about_x_rad, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return T * turn;
}

}  // namespace

// A frame whose pixels integrate the light over their area (aliasing included) through the distorted
// front camera, the panel ~90 px wide at 2.5 m and seen nearly face-on, where a tenth of a degree of
// tilt is a few hundredths of a pixel at the corners: the footprint model, fitted on the raw frame,
// finds the tilt from 2 degrees off (IPPE's error there) to a tenth of a degree, with gain and bias.
TEST_CASE("planar: the footprint refinement finds the tilt of a panel at 2.5 m in a frame that integrates each pixel") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  REQUIRE(camera.has_distortion());
  const cv::Mat panel = make_procedural_panel(cv::Size(640, 480), 11);
  const planar::AreaPoseRefiner refiner(panel, kW, kH, camera);
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.12, 0.05, -2.5), Eigen::Vector3d::Zero(), 0.03);
  const cv::Mat ideal = integrated_view(camera, panel, truth);
  cv::Mat frame;
  ideal.convertTo(frame, CV_8U, 0.7, 25.0);  // another exposure
  cv::Mat noise(frame.size(), CV_16SC1), wide;
  cv::RNG(3).fill(noise, cv::RNG::NORMAL, 0, 2.0);
  frame.convertTo(wide, CV_16S);
  wide += noise;
  wide.convertTo(frame, CV_8U);
  for (const auto& [ry, rx] : {std::pair{2.0, 0.0}, std::pair{-2.0, 1.0}, std::pair{0.5, -2.0}}) {
    const Eigen::Isometry3d start = tilted(truth, ry * kDeg, rx * kDeg);
    const planar::Se3Refinement r = refiner.refine(frame, start);
    INFO("start " << ry << ", " << rx << " deg: " << (r.refined ? "refined" : r.failure) << ", error "
                  << rotation_angle(r.T_cam_object.linear(), truth.linear()) / kDeg << " deg, residual " << r.residual_grey);
    REQUIRE(r.refined);
    CHECK(rotation_angle(r.T_cam_object.linear(), truth.linear()) < 0.15 * kDeg);
    CHECK((r.T_cam_object.translation() - truth.translation()).norm() < 0.005);
    CHECK(r.residual_grey < 3.0);  // 2.55: the noise (2), two roundings, the 8 x 8 sub-pixels' sampling
    CHECK(r.rotation_sigma_rad > 0.0);
    CHECK(r.rotation_sigma_rad < 1.0 * kDeg);
  }
  CHECK(refiner.selected_pixels() > 500);
}

TEST_CASE("planar: the footprint refinement says why it keeps the starting pose") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const cv::Mat panel = make_procedural_panel(cv::Size(320, 240), 11);
  const planar::AreaPoseRefiner refiner(panel, kW, kH, camera);
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.0, 0.0, -2.0), Eigen::Vector3d::Zero(), 0.0);
  const planar::Se3Refinement small = refiner.refine(cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), truth);
  CHECK_FALSE(small.refined);
  CHECK(std::string(small.failure).find("camera's size") != std::string::npos);
  CHECK(small.T_cam_object.isApprox(truth));
  // The panel far outside the image.
  const Eigen::Isometry3d aside = look_at_object(Eigen::Vector3d(6.0, 0.0, -2.0), Eigen::Vector3d(6.0, 0.0, 0.0), 0.0);
  const planar::Se3Refinement out = refiner.refine(cv::Mat(camera.height(), camera.width(), CV_8UC1, cv::Scalar(0)), aside);
  CHECK_FALSE(out.refined);
  CHECK(std::string(out.failure).find("too little") != std::string::npos);
  CHECK_THROWS_AS(AreaPoseRefiner(cv::Mat(), kW, kH, camera), std::invalid_argument);
  CHECK_THROWS_AS(AreaPoseRefiner(panel, 0.0, kH, camera), std::invalid_argument);
}
