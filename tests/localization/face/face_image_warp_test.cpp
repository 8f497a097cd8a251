// The face front end's own resampling (face_image_warp.hpp) against OpenCV's, pixel for pixel.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <random>

#include "localization/face/face_image_warp.hpp"

using namespace labo::face;

namespace {

cv::Mat random_image(cv::Size size, int seed) {
  cv::Mat image(size, CV_8UC1);
  cv::RNG(static_cast<std::uint64_t>(seed)).fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

}  // namespace

TEST_CASE("face image warp: warp_affine_8u equals cv::warpAffine (linear, border replicated) pixel for pixel") {
  // The landmark crop's transforms (scaled up 1-3x, turned +-35 degrees, widened 1-1.6x across the
  // face, placed anywhere, also past the frame's border), and general affine maps that shrink.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> scale(1.0, 3.0), angle(-0.6, 0.6), widen(1.0, 1.6), place(-80, 700),
      shear(-0.3, 0.3), shrink(0.3, 1.0);
  int images = 0;
  for (int k = 0; k < 60; ++k) {
    const cv::Mat src = random_image(k % 3 == 0 ? cv::Size(37, 23) : cv::Size(640, 360), k);
    cv::Matx23d M;
    if (k % 2 == 0) {
      const double s = scale(rng), a = angle(rng), w = widen(rng);
      const double cx = place(rng), cy = place(rng) / 2;
      M = cv::Matx23d(s * w * std::cos(a), s * w * std::sin(a), 0, -s * std::sin(a), s * std::cos(a), 0);
      M(0, 2) = 130 - (M(0, 0) * cx + M(0, 1) * cy);
      M(1, 2) = 120 - (M(1, 0) * cx + M(1, 1) * cy);
    } else {
      M = cv::Matx23d(shrink(rng), shear(rng), place(rng) / 4, shear(rng), shrink(rng), place(rng) / 4);
    }
    const cv::Size size(200 + k, 240 - k);
    cv::Mat reference, ours;
    cv::warpAffine(src, reference, M, size, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    warp_affine_8u(src, M, size, ours);
    INFO("case " << k);
    REQUIRE(ours.size() == reference.size());
    CHECK(cv::countNonZero(ours != reference) == 0);
    ++images;
  }
  CHECK(images == 60);
}

TEST_CASE("face image warp: remap_8u equals cv::remap (linear, border replicated) pixel for pixel") {
  // Piecewise-affine maps like the frontal view's, reaching past every border, with positions on the
  // 1/32 px steps, half-way between them (ties) and anywhere.
  const cv::Size source(640, 360);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> any(0.0f, 1.0f);
  for (int k = 0; k < 12; ++k) {
    const cv::Size size(256 + 3 * k, 256 - 2 * k);
    cv::Mat map_x(size, CV_32FC1), map_y(size, CV_32FC1);
    const float ox = -60.0f + 60.0f * static_cast<float>(k), oy = -40.0f + 40.0f * static_cast<float>(k % 6);
    for (int y = 0; y < size.height; ++y) {
      for (int x = 0; x < size.width; ++x) {
        const int kind = (x + 2 * y) % 3;
        const float jitter = kind == 0 ? static_cast<float>(rng() % 32) / 32.0f
                                       : kind == 1 ? static_cast<float>(rng() % 32) / 32.0f + 1.0f / 64.0f : any(rng);
        map_x.at<float>(y, x) = ox + 0.8f * static_cast<float>(x) + 0.1f * static_cast<float>(y) + jitter;
        map_y.at<float>(y, x) = oy - 0.1f * static_cast<float>(x) + 0.9f * static_cast<float>(y) - jitter;
      }
    }
    const cv::Mat src = random_image(source, 100 + k);
    cv::Mat reference, ours;
    cv::remap(src, reference, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    remap_8u(src, map_x, map_y, ours);
    INFO("case " << k);
    REQUIRE(ours.size() == reference.size());
    CHECK(cv::countNonZero(ours != reference) == 0);
  }
}

TEST_CASE("face image warp: sized_view keeps one buffer while the size changes by a few pixels") {
  cv::Mat storage, view;
  sized_view(storage, cv::Size(256, 256), CV_8UC1, view);
  const uchar* buffer = storage.data;
  CHECK(view.size() == cv::Size(256, 256));
  CHECK(view.data == buffer);
  for (int d = -20; d <= 20; d += 5) {
    sized_view(storage, cv::Size(256 + d, 256 - d / 2), CV_8UC1, view);
    CHECK(view.size() == cv::Size(256 + d, 256 - d / 2));
    CHECK(storage.data == buffer);
  }
  sized_view(storage, cv::Size(400, 300), CV_8UC1, view);  // beyond the room: grown
  CHECK(view.size() == cv::Size(400, 300));
  CHECK(storage.cols >= 400);
  sized_view(storage, cv::Size(40, 30), CV_32FC1, view);  // another type: its own buffer
  CHECK(view.type() == CV_32FC1);
}
