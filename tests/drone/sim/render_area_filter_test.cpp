#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "render_fixtures.hpp"

using namespace labo;
using namespace labo::lab;
using namespace labo::sim;
using namespace labo::test;

namespace {

// A small window of the AR.Drone's front camera (same focal length, no lens distortion), drawn at
// `factor` times its resolution: the same pixel grid subdivided factor x factor.
CameraIntrinsics window(int factor) {
  CameraIntrinsics k;
  k.width = 128 * factor;
  k.height = 96 * factor;
  k.fx = k.fy = 562.0 * factor;
  k.cx = 63.5 * factor + 0.5 * (factor - 1);
  k.cy = 47.5 * factor + 0.5 * (factor - 1);
  return k;
}

cv::Mat grey_render(const LabDescription& lab, int factor, const SceneState& scene) {
  LabRenderer renderer(lab, {window(factor), PinholeCamera::ardrone2_bottom().intrinsics()}, std::nullopt, 1, sharp_options());
  cv::Mat bgr, gray, f;
  renderer.render(CameraId::Front, scene, bgr);
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  gray.convertTo(f, CV_32F);
  if (factor > 1) cv::resize(f, f, cv::Size(128, 96), 0, 0, cv::INTER_AREA);  // each pixel's mean
  return f;
}

}  // namespace

TEST_CASE("render: a texture's box mean is the exact mean of the texels the box covers") {
  cv::Mat texels(23, 37, CV_8UC3);
  cv::RNG rng(5);
  rng.fill(texels, cv::RNG::UNIFORM, 0, 256);
  TextureMap tex(texels);
  REQUIRE_FALSE(tex.has_area_table());
  REQUIRE(tex.build_area_table());
  REQUIRE(tex.has_area_table());
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // A box in 1/256 texels, anywhere in the texture, 0.3 to 12 texels a side.
    const int x0 = rng.uniform(0, 30 * 256), y0 = rng.uniform(0, 16 * 256);
    const int x1 = std::min(37 * 256, x0 + rng.uniform(77, 12 * 256)), y1 = std::min(23 * 256, y0 + rng.uniform(77, 12 * 256));
    double sum[3] = {0, 0, 0};
    for (int y = y0 / 256; y * 256 < y1; ++y) {
      for (int x = x0 / 256; x * 256 < x1; ++x) {
        const double w = (std::min(x1, (x + 1) * 256) - std::max(x0, x * 256)) * (std::min(y1, (y + 1) * 256) - std::max(y0, y * 256)) / 65536.0;
        const cv::Vec3b& c = texels.at<cv::Vec3b>(y, x);
        for (int k = 0; k < 3; ++k) sum[k] += w * c[k];
      }
    }
    const double area = (x1 - x0) * (y1 - y0) / 65536.0;
    const std::uint32_t mean = tex.box_mean(x0, y0, x1, y1);
    INFO("box " << x0 / 256.0 << ".." << x1 / 256.0 << " x " << y0 / 256.0 << ".." << y1 / 256.0);
    CHECK(std::abs(texel_b(mean) - sum[0] / area) <= 0.51);
    CHECK(std::abs(texel_g(mean) - sum[1] / area) <= 0.51);
    CHECK(std::abs(texel_r(mean) - sum[2] / area) <= 0.51);
    ++checked;
  }
  CHECK(checked == 200);
}

TEST_CASE("render: an instrument panel seen from afar records each pixel's mean, as 8x8 sub-pixels do") {
  // The oscilloscope (0.40 m, its 800 px template) from 2.5 m, a little off-axis: ~90 px wide, ~9 texels
  // per pixel. A camera's pixel integrates the light over its area; the reference is the mean of
  // 8 x 8 sub-pixels, each about one texel (level 0, bilinear). Without area filtering the renderer
  // would sample the mip level of ~1 texel per pixel bilinearly at the pixel's centre: its blur and
  // aliasing depend on the sub-pixel phase (here without the area table: mean |difference| about
  // 3 grey levels inside the panel, largest tens).
  const LabDescription lab = load_lab_description(default_lab_path());
  const InstrumentSpec* scope = lab.find_instrument("oscilloscope");
  REQUIRE(scope != nullptr);
  const Eigen::Vector3d centre = scope->T_world_object.translation();
  const Eigen::Vector3d towards_viewer = -scope->T_world_object.linear().col(2);
  const Eigen::Vector3d eye = centre + 2.5 * towards_viewer + Eigen::Vector3d(0.07, 0.11, 0.04);
  const SceneState scene = still_scene(body_looking_at(eye, centre + Eigen::Vector3d(0, 0.02, 0.01)));
  const cv::Mat frame = grey_render(lab, 1, scene);
  const cv::Mat reference = grey_render(lab, 8, scene);
  // The panel's interior, 3 px in from its edges.
  const PinholeCamera camera(window(1));
  const Eigen::Isometry3d T_cam_world = (scene.T_world_body * T_body_cam_front()).inverse();
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      const auto p = camera.project(T_cam_world * scope->T_world_object * Eigen::Vector3d(sx * scope->width_m, sy * scope->height_m, 0));
      REQUIRE(p);
      x0 = std::min(x0, p->x()), x1 = std::max(x1, p->x()), y0 = std::min(y0, p->y()), y1 = std::max(y1, p->y());
    }
  }
  REQUIRE(x1 - x0 > 80);
  REQUIRE(x1 - x0 < 100);
  const cv::Rect inside(static_cast<int>(std::ceil(x0)) + 3, static_cast<int>(std::ceil(y0)) + 3,
                        static_cast<int>(x1 - x0) - 6, static_cast<int>(y1 - y0) - 6);
  REQUIRE((inside & cv::Rect(0, 0, 128, 96)) == inside);
  cv::Mat difference;
  cv::absdiff(frame(inside), reference(inside), difference);
  const double mean_abs = cv::mean(difference)[0];
  double largest = 0;
  cv::minMaxLoc(difference, nullptr, &largest);
  INFO("mean |difference| " << mean_abs << ", largest " << largest);
  CHECK(mean_abs < 0.5);
  CHECK(largest < 4.0);
}
