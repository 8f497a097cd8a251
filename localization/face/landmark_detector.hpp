#pragma once
// The 68 face landmarks: dlib's trained ensemble-of-regression-trees model (Kazemi & Sullivan; iBUG
// 300-W, HOG-detector boxes), evaluated by LaboDrone's own allocation-free cascade
// (landmark_cascade.hpp), landmark for landmark as dlib's shape_predictor. dlib stays out of this header.
#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>

namespace labo::face {

class LandmarkDetector {
 public:
  // Throws std::runtime_error naming the file and what is wrong when it is missing or not a usable
  // dlib shape predictor (landmark_cascade.hpp), or when the predictor does not give 68 points.
  explicit LandmarkDetector(const std::filesystem::path& shape_predictor_file);
  ~LandmarkDetector();
  LandmarkDetector(LandmarkDetector&&) noexcept;
  LandmarkDetector& operator=(LandmarkDetector&&) noexcept;

  // The 68 landmarks (2 x 68, full-frame pixels, distorted as in the image) for a face box.
  // `upright_rad`: the face's in-plane angle in the image (its eye line, clockwise in image
  // coordinates); the crop is turned by it so that the predictor sees an upright face, as in its
  // training set, and the landmarks are turned back. `box` is then the box of the upright face
  // around the same centre.
  // `widen` (>= 1) stretches the upright crop across the face: a head turned by yaw looks narrower
  // by about cos(yaw), and the predictor, trained mostly on frontal faces, pulls a narrow face's
  // landmarks back towards a frontal shape.
  void detect(const cv::Mat& gray, const cv::Rect2d& box, Eigen::Matrix2Xd& landmarks, double upright_rad = 0,
              double widen = 1);

  // The predictor on an image already prepared for it (e.g. face/frontal_view.hpp's view), `rect`
  // the face's box there; landmarks in that image's pixels (integers: the predictor rounds, as dlib's).
  void detect_in(const cv::Mat& prepared, const cv::Rect2d& rect, Eigen::Matrix2Xd& landmarks);

  // The face box, axis-aligned and square, in which the predictor's mean shape lies over the eyes
  // and nose of `landmarks` (2 x 68; the similarity's rotation is taken out, its scale and place
  // kept). A detector's box is only roughly the face: the cascade does not move far from the box
  // it starts in, and a box a fifth too large leaves the mouth and chin stretched far below the
  // face (the HOG detector's next pyramid level, on small faces over clutter). An empty box when the
  // eyes and nose coincide. Throws std::invalid_argument for other than 68 landmarks.
  cv::Rect2d box_for(const Eigen::Matrix2Xd& landmarks) const;

  static std::filesystem::path default_path() { return "/usr/share/dlib/shape_predictor_68_face_landmarks.dat"; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::face
