#include "localization/planar/template_strength.hpp"

#include <algorithm>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace labo::planar {

namespace {

constexpr int kCells = 8;
constexpr double kTexturedGradient = 6.0;  // mean |gradient| per pixel (grey levels) of a textured cell

double textured_fraction(const cv::Mat& gray) {
  cv::Mat gx, gy, magnitude;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3, 0.125);  // 1/8: the kernel's weight, so values are grey levels per pixel
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3, 0.125);
  cv::magnitude(gx, gy, magnitude);
  int textured = 0;
  for (int i = 0; i < kCells; ++i) {
    for (int j = 0; j < kCells; ++j) {
      const cv::Rect cell(j * gray.cols / kCells, i * gray.rows / kCells, gray.cols / kCells, gray.rows / kCells);
      textured += cv::mean(magnitude(cell))[0] >= kTexturedGradient;
    }
  }
  return static_cast<double>(textured) / (kCells * kCells);
}

}  // namespace

TemplateStrength measure_template_strength(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1 || gray.cols < kCells || gray.rows < kCells)
    throw std::invalid_argument("template strength: an 8-bit grey image of at least 8 x 8 pixels is needed");
  cv::Mat scaled = gray;
  const double scale = static_cast<double>(kMeasureSidePx) / std::max(gray.cols, gray.rows);
  if (scale < 1.0) cv::resize(gray, scaled, cv::Size(), scale, scale, cv::INTER_AREA);
  TemplateStrength s;
  std::vector<cv::KeyPoint> keypoints;
  cv::SIFT::create()->detect(scaled, keypoints);
  s.sift_keypoints = static_cast<int>(keypoints.size());
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(scaled, corners, 500, 0.01, std::max(3.0, scaled.cols / 100.0));
  s.strong_corners = static_cast<int>(corners.size());
  s.textured_fraction = textured_fraction(scaled);
  return s;
}

std::string template_weakness(const TemplateStrength& s, const TemplateStrengthLimits& limits) {
  std::string why;
  const auto add = [&](const std::string& part) { why += (why.empty() ? "" : "; ") + part; };
  if (s.sift_keypoints < limits.min_sift_keypoints)
    add(std::to_string(s.sift_keypoints) + " SIFT keypoints, at least " + std::to_string(limits.min_sift_keypoints) + " needed");
  if (s.strong_corners < limits.min_strong_corners)
    add(std::to_string(s.strong_corners) + " strong corners, at least " + std::to_string(limits.min_strong_corners) + " needed");
  if (s.textured_fraction < limits.min_textured_fraction)
    add(std::to_string(static_cast<int>(s.textured_fraction * 100 + 0.5)) + " % of the panel textured, at least " +
        std::to_string(static_cast<int>(limits.min_textured_fraction * 100 + 0.5)) + " % needed");
  return why;
}

}  // namespace labo::planar
