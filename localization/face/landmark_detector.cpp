#include "localization/face/landmark_detector.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/Geometry>
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

void LandmarkDetector::detect(const cv::Mat& gray, const cv::Rect2d& box, Eigen::Matrix2Xd& landmarks,
                              double upright_rad, double widen) {
  if (gray.empty() || gray.type() != CV_8UC1) throw std::invalid_argument("landmark detector: expected an 8-bit grey image");
  if (!(box.width > 0 && box.height > 0) || (box & cv::Rect2d(0, 0, gray.cols, gray.rows)).area() <= 0) {
    throw std::invalid_argument("landmark detector: face box lies outside the image");
  }
  // dlib returns integer pixels: a small face is resampled so that its box is about
  // `kWorkingWidthPx` wide, which keeps the rounding well under a pixel of the original image.
  constexpr double kWorkingWidthPx = 160;
  const double scale = std::max(1.0, kWorkingWidthPx / box.width);
  const double margin = 0.3 * std::max(box.width, box.height);
  if (!(widen >= 1 && widen <= 3)) throw std::invalid_argument("landmark detector: widen must be within 1-3");
  const cv::Size work_size(static_cast<int>(std::ceil((box.width + 2 * margin) * scale * widen)),
                           static_cast<int>(std::ceil((box.height + 2 * margin) * scale)));
  // Full-frame pixel p -> working pixel q = scale * Rot(-upright) * (p - c) + q_c (pixel centres).
  const Eigen::Vector2d c(box.x + box.width / 2 - 0.5, box.y + box.height / 2 - 0.5);
  const Eigen::Vector2d q_c(work_size.width / 2.0 - 0.5, work_size.height / 2.0 - 0.5);
  const Eigen::Matrix2d to_work =
      scale * Eigen::Vector2d(widen, 1).asDiagonal() * Eigen::Rotation2Dd(-upright_rad).toRotationMatrix();
  const Eigen::Vector2d offset = q_c - to_work * c;
  const cv::Matx23d M(to_work(0, 0), to_work(0, 1), offset.x(), to_work(1, 0), to_work(1, 1), offset.y());
  // Pixels beyond the image repeat its border; a face cut by the border is refused from its landmarks.
  cv::warpAffine(gray, impl_->work, M, work_size, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  const dlib::cv_image<unsigned char> image(impl_->work);
  const double half_w = box.width * scale * widen / 2, half_h = box.height * scale / 2;
  const dlib::rectangle rect(std::lround(q_c.x() - half_w + 0.5), std::lround(q_c.y() - half_h + 0.5),
                             std::lround(q_c.x() + half_w - 0.5), std::lround(q_c.y() + half_h - 0.5));
  const dlib::full_object_detection shape = impl_->predictor(image, rect);
  const Eigen::Matrix2d to_frame = to_work.inverse();
  landmarks.resize(2, 68);
  for (unsigned long i = 0; i < 68; ++i) {
    const Eigen::Vector2d q(static_cast<double>(shape.part(i).x()), static_cast<double>(shape.part(i).y()));
    landmarks.col(static_cast<Eigen::Index>(i)) = to_frame * (q - offset);
  }
}

void LandmarkDetector::detect_in(const cv::Mat& prepared, const cv::Rect2d& rect, Eigen::Matrix2Xd& landmarks) {
  if (prepared.empty() || prepared.type() != CV_8UC1) throw std::invalid_argument("landmark detector: expected an 8-bit grey image");
  if (!(rect.width > 0 && rect.height > 0)) throw std::invalid_argument("landmark detector: empty face box");
  const dlib::cv_image<unsigned char> image(prepared);
  const dlib::rectangle r(std::lround(rect.x), std::lround(rect.y), std::lround(rect.x + rect.width - 1),
                          std::lround(rect.y + rect.height - 1));
  const dlib::full_object_detection shape = impl_->predictor(image, r);
  landmarks.resize(2, 68);
  for (unsigned long i = 0; i < 68; ++i) {
    landmarks.col(static_cast<Eigen::Index>(i)) << static_cast<double>(shape.part(i).x()), static_cast<double>(shape.part(i).y());
  }
}

}  // namespace labo::face
