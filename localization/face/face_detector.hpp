#pragma once
// Face boxes in a grey frame with dlib's HOG frontal face detector (five HOG filters: front, left- and
// right-looking, tilted). Two searches: around the last face, with the region upsampled so that faces
// down to ~40 px wide are found (the detector's window is 80 px), and over the whole frame at a chosen
// scale when the face is lost. dlib stays out of this header.
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace labo::face {

struct FaceBox {
  cv::Rect2d box;   // full-frame pixels
  double score = 0; // detector confidence (HOG SVM margin)
};

struct FaceDetectorOptions {
  double region_scale = 2.2;      // search region = last box scaled about its centre
  double target_face_px = 90;     // the region is resampled so the last face is about this wide
  double max_upsample = 2.5;
  double adjust_threshold = 0.0;  // added to dlib's detection threshold
};

class FaceDetector {
 public:
  explicit FaceDetector(FaceDetectorOptions options = {});
  ~FaceDetector();
  FaceDetector(FaceDetector&&) noexcept;
  FaceDetector& operator=(FaceDetector&&) noexcept;

  // All faces in the frame, the frame resampled by `scale` first (0.5: faster, only big faces; 2:
  // slow, faces down to ~40 px). Boxes in full-frame pixels, best score first.
  std::vector<FaceBox> detect_full(const cv::Mat& gray, double scale);
  // Faces in a region around `previous`, resampled for its size.
  std::vector<FaceBox> detect_around(const cv::Mat& gray, const cv::Rect2d& previous);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::face
