#include "localization/face/face_detector.hpp"

#include <algorithm>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/opencv/cv_image.h>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace labo::face {

struct FaceDetector::Impl {
  FaceDetectorOptions options;
  dlib::frontal_face_detector hog = dlib::get_frontal_face_detector();
  cv::Mat resized;
  std::vector<dlib::rect_detection> detections;

  // Detects in `gray(roi)` resampled by `scale`; appends boxes in full-frame pixels.
  void detect(const cv::Mat& gray, const cv::Rect& roi, double scale, std::vector<FaceBox>& out) {
    const cv::Mat view = gray(roi);
    const cv::Size size(std::max(1, static_cast<int>(std::lround(roi.width * scale))),
                        std::max(1, static_cast<int>(std::lround(roi.height * scale))));
    if (size.width < 80 || size.height < 80) return;  // smaller than one HOG window
    if (size == view.size()) {
      view.copyTo(resized);  // dlib's cv_image needs a continuous 8-bit image
    } else {
      cv::resize(view, resized, size, 0, 0, scale > 1 ? cv::INTER_LINEAR : cv::INTER_AREA);
    }
    const dlib::cv_image<unsigned char> image(resized);
    detections.clear();
    hog(image, detections, options.adjust_threshold);
    const double sx = static_cast<double>(roi.width) / size.width, sy = static_cast<double>(roi.height) / size.height;
    for (const auto& d : detections) {
      const auto& r = d.rect;
      out.push_back({cv::Rect2d(roi.x + r.left() * sx, roi.y + r.top() * sy, r.width() * sx, r.height() * sy),
                     d.detection_confidence});
    }
  }
};

FaceDetector::FaceDetector(FaceDetectorOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
}
FaceDetector::~FaceDetector() = default;
FaceDetector::FaceDetector(FaceDetector&&) noexcept = default;
FaceDetector& FaceDetector::operator=(FaceDetector&&) noexcept = default;

namespace {
void check_gray(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("face detector: expected a non-empty 8-bit grey image");
  }
}
void sort_by_score(std::vector<FaceBox>& boxes) {
  std::sort(boxes.begin(), boxes.end(), [](const FaceBox& a, const FaceBox& b) { return a.score > b.score; });
}
}  // namespace

std::vector<FaceBox> FaceDetector::detect_full(const cv::Mat& gray, double scale) {
  check_gray(gray);
  std::vector<FaceBox> out;
  impl_->detect(gray, cv::Rect(0, 0, gray.cols, gray.rows), scale, out);
  sort_by_score(out);
  return out;
}

std::vector<FaceBox> FaceDetector::detect_around(const cv::Mat& gray, const cv::Rect2d& previous) {
  check_gray(gray);
  const auto& o = impl_->options;
  const double side = std::max(previous.width, previous.height);
  const cv::Point2d c(previous.x + previous.width / 2, previous.y + previous.height / 2);
  const double half = side * o.region_scale / 2;
  const cv::Rect region = cv::Rect(cv::Point(static_cast<int>(c.x - half), static_cast<int>(c.y - half)),
                                   cv::Point(static_cast<int>(c.x + half), static_cast<int>(c.y + half))) &
                          cv::Rect(0, 0, gray.cols, gray.rows);
  std::vector<FaceBox> out;
  if (region.area() <= 0) return out;
  const double scale = std::clamp(o.target_face_px / std::max(side, 1.0), 0.25, o.max_upsample);
  impl_->detect(gray, region, scale, out);
  sort_by_score(out);
  return out;
}

}  // namespace labo::face
