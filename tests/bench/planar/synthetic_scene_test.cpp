#include <catch2/catch.hpp>

#include <cmath>

#include "bench/planar/synthetic_scene.hpp"
#include "tests/localization/planar/supersampled_pixel.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

constexpr double kW = 0.40, kH = 0.30;
constexpr uchar kBackground = 120;  // PlanarViewRenderer's flat grey without a wall

}  // namespace

// The renderer the planar benchmark's synthetic sequences use, checked on its own (no tracker): every
// other pixel over and around the panel against a reference of 16 x 16 rays per pixel (the texels
// piecewise constant), from far (3.5 texels per pixel, where resampling twice would displace the
// detail) to near (magnified), face-on, tilted and rolled, through the distorted front camera.
TEST_CASE("planar: the synthetic renderer's pixels integrate the panel over their footprint") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const cv::Mat panel = make_procedural_panel(cv::Size(320, 240), 11);
  const PlanarViewRenderer renderer(camera, cv::Mat(), 0.0025);
  for (const Eigen::Isometry3d& T : {look_at_object(Eigen::Vector3d(0.1, 0.04, -2.6), Eigen::Vector3d::Zero(), 0.03),
                                     look_at_object(Eigen::Vector3d(0.9, -0.2, -1.1), Eigen::Vector3d(0.05, 0, 0), 0.35),
                                     look_at_object(Eigen::Vector3d(-0.05, 0.02, -0.6), Eigen::Vector3d::Zero(), -0.1)}) {
    const cv::Mat frame = renderer.render(panel, kW, kH, T);
    const Eigen::Isometry3d T_object_cam = T.inverse();
    double sum_squares = 0, worst = 0;
    int pixels = 0;
    for (int y = 0; y < frame.rows; ++y) {
      for (int x = y % 2; x < frame.cols; x += 2) {  // every other pixel (a checkerboard): the reference is costly
        // The panel and a 2-pixel ring around it (its blended edge).
        bool near_panel = false;
        for (int dy = -2; dy <= 2 && !near_panel; dy += 2) {
          for (int dx = -2; dx <= 2 && !near_panel; dx += 2) {
            const Eigen::Vector3d ray = T_object_cam.linear() * camera.unproject(Eigen::Vector2d(x + dx, y + dy));
            const double s = -T_object_cam.translation().z() / ray.z();
            const Eigen::Vector3d p = T_object_cam.translation() + s * ray;
            near_panel = s > 0 && std::abs(p.x()) < 0.5 * kW && std::abs(p.y()) < 0.5 * kH;
          }
        }
        if (!near_panel) continue;
        const double e = frame.at<uchar>(y, x) - supersampled_pixel(camera, panel, kW, kH, T_object_cam, x, y, 16, kBackground);
        sum_squares += e * e;
        worst = std::max(worst, std::abs(e));
        ++pixels;
      }
    }
    const double rms = std::sqrt(sum_squares / std::max(1, pixels));
    INFO("pixels " << pixels << ", RMS " << rms << ", worst " << worst << " grey levels");
    REQUIRE(pixels > 1000);
    CHECK(rms < 0.6);     // the 8-bit rounding alone is 0.29
    CHECK(worst < 4.0);   // resampling twice (area-shrunk, then bilinear) is off by tens of grey levels
  }
}
