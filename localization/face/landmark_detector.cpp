#include "localization/face/landmark_detector.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <fstream>
#include <stdexcept>

namespace labo::face {

struct LandmarkDetector::Impl {
  dlib::shape_predictor predictor;
  cv::Mat work;
};

LandmarkDetector::LandmarkDetector(const std::filesystem::path& file) : impl_(std::make_unique<Impl>()) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the 68-point shape predictor (package libdlib-data)");
  try {
    dlib::deserialize(impl_->predictor, in);
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": not a dlib shape predictor: " + e.what());
  }
  if (impl_->predictor.num_parts() != 68) {
    throw std::runtime_error(file.string() + ": predicts " + std::to_string(impl_->predictor.num_parts()) +
                             " landmarks, expected 68");
  }
}
LandmarkDetector::~LandmarkDetector() = default;
LandmarkDetector::LandmarkDetector(LandmarkDetector&&) noexcept = default;
LandmarkDetector& LandmarkDetector::operator=(LandmarkDetector&&) noexcept = default;

void LandmarkDetector::detect(const cv::Mat& gray, const cv::Rect2d& box, Eigen::Matrix2Xd& landmarks) {
  if (gray.empty() || gray.type() != CV_8UC1) throw std::invalid_argument("landmark detector: expected an 8-bit grey image");
  // dlib returns integer pixels: a small face is resampled so that its box is about
  // `kWorkingWidthPx` wide, which keeps the rounding well under a pixel of the original image.
  constexpr double kWorkingWidthPx = 160;
  const double scale = std::max(1.0, kWorkingWidthPx / std::max(box.width, 1.0));
  const double margin = 0.3 * std::max(box.width, box.height);
  const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(std::floor(box.x - margin)), static_cast<int>(std::floor(box.y - margin))),
                                cv::Point(static_cast<int>(std::ceil(box.x + box.width + margin)),
                                          static_cast<int>(std::ceil(box.y + box.height + margin)))) &
                       cv::Rect(0, 0, gray.cols, gray.rows);
  if (roi.area() <= 0) throw std::invalid_argument("landmark detector: face box lies outside the image");
  if (scale > 1.0) {
    cv::resize(gray(roi), impl_->work, cv::Size(), scale, scale, cv::INTER_LINEAR);
  } else {
    gray(roi).copyTo(impl_->work);
  }
  const dlib::cv_image<unsigned char> image(impl_->work);
  const auto to_work = [&](double v, int origin) { return std::lround((v - origin + 0.5) * scale - 0.5); };
  const dlib::rectangle rect(to_work(box.x, roi.x), to_work(box.y, roi.y), to_work(box.x + box.width, roi.x) - 1,
                             to_work(box.y + box.height, roi.y) - 1);
  const dlib::full_object_detection shape = impl_->predictor(image, rect);
  landmarks.resize(2, 68);
  for (unsigned long i = 0; i < 68; ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    landmarks(0, c) = roi.x + (static_cast<double>(shape.part(i).x()) + 0.5) / scale - 0.5;
    landmarks(1, c) = roi.y + (static_cast<double>(shape.part(i).y()) + 0.5) / scale - 0.5;
  }
}

}  // namespace labo::face
