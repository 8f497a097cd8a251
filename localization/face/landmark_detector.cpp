#include "localization/face/landmark_detector.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "localization/face/face_image_warp.hpp"
#include "localization/face/landmark_cascade.hpp"

namespace labo::face {

struct LandmarkDetector::Impl {
  explicit Impl(const std::filesystem::path& file) : cascade(file) {}
  LandmarkCascade cascade;
  cv::Mat work_storage, work;  // the crop: a view of the storage, which only grows
};

LandmarkDetector::LandmarkDetector(const std::filesystem::path& file) : impl_(std::make_unique<Impl>(file)) {
  if (impl_->cascade.landmark_count() != 68) {
    throw std::runtime_error(file.string() + ": predicts " + std::to_string(impl_->cascade.landmark_count()) +
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
  // As cv::warpAffine (linear, border replicated) computes it, without its per-call allocations.
  warp_affine_8u(gray, M, work_size, sized_view(impl_->work_storage, work_size, CV_8UC1, impl_->work));
  const double half_w = box.width * scale * widen / 2, half_h = box.height * scale / 2;
  const PixelBox rect{std::lround(q_c.x() - half_w + 0.5), std::lround(q_c.y() - half_h + 0.5),
                      std::lround(q_c.x() + half_w - 0.5), std::lround(q_c.y() + half_h - 0.5)};
  impl_->cascade.fit(impl_->work, rect, landmarks);
  const Eigen::Matrix2d to_frame = to_work.inverse();
  for (Eigen::Index i = 0; i < 68; ++i) landmarks.col(i) = to_frame * (landmarks.col(i) - offset);
}

cv::Rect2d LandmarkDetector::box_for(const Eigen::Matrix2Xd& landmarks) const {
  if (landmarks.cols() != 68) throw std::invalid_argument("landmark detector: box_for expects 68 landmarks");
  // The nose (27-35) and the eyes (36-47): the points the predictor places best whatever its box.
  constexpr int kFirst = 27, kCount = 21;
  Eigen::Vector2d m_mean = Eigen::Vector2d::Zero(), l_mean = Eigen::Vector2d::Zero();
  for (int i = kFirst; i < kFirst + kCount; ++i) {
    m_mean += impl_->cascade.mean_landmark(i);
    l_mean += landmarks.col(i);
  }
  m_mean /= kCount;
  l_mean /= kCount;
  double dot = 0, cross = 0, m_spread = 0;
  for (int i = kFirst; i < kFirst + kCount; ++i) {
    const Eigen::Vector2d m = impl_->cascade.mean_landmark(i) - m_mean, l = landmarks.col(i) - l_mean;
    dot += m.dot(l);
    cross += m.x() * l.y() - m.y() * l.x();
    m_spread += m.squaredNorm();
  }
  if (!(m_spread > 0)) throw std::logic_error("landmark detector: degenerate mean shape");
  // The least-squares similarity (scale times rotation) from the mean shape to the landmarks; its
  // scale is the box side in pixels.
  const Eigen::Matrix2d similarity = (Eigen::Matrix2d() << dot, -cross, cross, dot).finished() / m_spread;
  const double side = std::hypot(dot, cross) / m_spread;
  const Eigen::Vector2d centre = l_mean - similarity * (m_mean - Eigen::Vector2d(0.5, 0.5));
  return {centre.x() - side / 2, centre.y() - side / 2, side, side};
}

void LandmarkDetector::detect_in(const cv::Mat& prepared, const cv::Rect2d& rect, Eigen::Matrix2Xd& landmarks) {
  if (prepared.empty() || prepared.type() != CV_8UC1) throw std::invalid_argument("landmark detector: expected an 8-bit grey image");
  if (!(rect.width > 0 && rect.height > 0)) throw std::invalid_argument("landmark detector: empty face box");
  const PixelBox box{std::lround(rect.x), std::lround(rect.y), std::lround(rect.x + rect.width - 1),
                     std::lround(rect.y + rect.height - 1)};
  impl_->cascade.fit(prepared, box, landmarks);
}

}  // namespace labo::face
