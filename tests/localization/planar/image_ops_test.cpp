// The planar localizer's allocation-free image operations against the OpenCV calls they replace:
// equal pixel for pixel.
#include <catch2/catch.hpp>

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/planar/image_ops.hpp"

using namespace labo;
using namespace labo::planar;

namespace {

cv::Mat random_image(cv::Size size, int seed) {
  cv::Mat image(size, CV_8UC1);
  cv::RNG rng(static_cast<uint64>(seed));
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  // Also smooth structure, as in a camera frame, not only noise.
  cv::Mat ramp(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) ramp.at<uchar>(y, x) = cv::saturate_cast<uchar>(128 + 100 * std::sin(0.07 * x + 0.05 * y));
  }
  cv::addWeighted(image, 0.5, ramp, 0.5, 0.0, image);
  return image;
}

}  // namespace

TEST_CASE("image ops: pyr_down_8u equals cv::pyrDown pixel for pixel") {
  std::vector<int> scratch;
  cv::Mat ours;
  int seed = 1;
  for (const cv::Size size : {cv::Size(640, 360), cv::Size(320, 180), cv::Size(161, 91), cv::Size(80, 45), cv::Size(7, 5),
                              cv::Size(3, 3), cv::Size(2, 2), cv::Size(1, 4)}) {
    const cv::Mat src = random_image(size, seed++);
    cv::Mat reference;
    cv::pyrDown(src, reference);
    pyr_down_8u(src, ours, scratch);
    INFO(size);
    REQUIRE(ours.size() == reference.size());
    CHECK(cv::countNonZero(ours != reference) == 0);
  }
}

TEST_CASE("image ops: LinearRemap8u equals cv::remap (linear, constant border) pixel for pixel") {
  // The front camera's undistortion maps (what the planar localizer uses), and maps reaching past
  // every border, with positions on and between the 1/32 px steps.
  const cv::Size size(640, 360);
  const cv::Matx33d K(569.8, 0, 318.4, 0, 566.1, 183.7, 0, 0, 1);
  const cv::Mat distortion = (cv::Mat_<double>(1, 5) << -0.52, 0.31, 0.001, -0.002, -0.09);
  cv::Mat undistort_x, undistort_y;
  cv::initUndistortRectifyMap(K, distortion, cv::Mat(), K, size, CV_32FC1, undistort_x, undistort_y);
  cv::Mat wide_x(size, CV_32FC1), wide_y(size, CV_32FC1);
  cv::RNG rng(7);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const float jitter = (x + y) % 3 == 0 ? std::round(static_cast<float>(rng.uniform(0.0, 32.0))) / 32.0f + 1.0f / 64.0f
                                            : static_cast<float>(rng.uniform(0.0, 1.0));
      wide_x.at<float>(y, x) = -3.0f + 1.01f * static_cast<float>(x) + jitter;
      wide_y.at<float>(y, x) = -3.0f + 1.02f * static_cast<float>(y) - jitter;
    }
  }
  int seed = 11;
  for (const auto& maps : {std::pair{undistort_x, undistort_y}, std::pair{wide_x, wide_y}}) {
    const planar::LinearRemap8u remap(maps.first, maps.second, size);
    for (int k = 0; k < 3; ++k) {
      const cv::Mat src = random_image(size, seed++);
      cv::Mat reference, ours;
      cv::remap(src, reference, maps.first, maps.second, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
      remap.apply(src, ours);
      CHECK(cv::countNonZero(ours != reference) == 0);
    }
  }
}

TEST_CASE("image ops: GaussianBlur8u equals cv::GaussianBlur on a region of interest pixel for pixel") {
  // (Sensitive: the same passes without fused multiply-adds differ from OpenCV in 1-2 pixels of 500 000.)
  const cv::Size size(640, 360);
  std::vector<float> scratch;
  int seed = 21;
  for (const double sigma : {0.5, 0.7, 1.0, 1.5}) {
    const planar::GaussianBlur8u blur(sigma);
    for (const cv::Rect roi : {cv::Rect(0, 0, 640, 359), cv::Rect(100, 50, 200, 120), cv::Rect(0, 7, 33, 300), cv::Rect(601, 300, 39, 60),
                               cv::Rect(1, 1, 17, 5), cv::Rect(250, 0, 129, 1)}) {
      const cv::Mat image = random_image(size, seed++);
      cv::Mat reference(size, CV_8UC1, cv::Scalar(0)), ours(size, CV_8UC1, cv::Scalar(0));
      cv::Mat reference_roi = reference(roi);
      cv::GaussianBlur(image(roi), reference_roi, cv::Size(0, 0), sigma);
      blur.apply(image, roi, ours, scratch);
      INFO("sigma " << sigma << ", roi " << roi);
      CHECK(cv::countNonZero(ours(roi) != reference(roi)) == 0);
    }
  }
}
