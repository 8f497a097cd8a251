#pragma once
// What the two detectors of the paper's Fig. 3 give: a first homography (working template px ->
// image px) that the tracker then refines. Far: TemplateMatchDetector (template_detector.hpp). Near:
// FeatureMatchDetector here: features of the template computed once, the frame's features, Lowe's
// ratio test, a RANSAC homography, found with at least N inliers and a convex quadrilateral.
//
// The features (PlanarConfig::near_detector): the paper's SIFT, or the binary ORB, BRISK or AKAZE
// (OpenCV 4.6), on the frame resized by `near_frame_scale` (0.5: the frame halved, SIFT's costly
// first octaves gone). `labodrone-bench bench vision --part detectors` compares them.
// The constructor runs the detector once on a frame of the camera's size, so that OpenCV's first-call
// costs (its buffers' page faults, ~150 ms for SIFT on this machine) are paid at template load and
// not by the first frame. OpenCV's feature code allocates its pyramid and keypoints inside every call;
// the frame's keypoints, descriptors, matches and point lists are kept here between frames.
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include "localization/planar/detect/binary_matcher.hpp"
#include "localization/planar/planar_config.hpp"

namespace labo::planar {

struct Detection {
  bool found = false;
  cv::Matx33d H = cv::Matx33d::eye();  // working template px -> image px
  double score = 0;                    // best correlation (template) or inlier ratio (features)
  int inliers = 0;                     // features only
  int matches = 0;                     // features only: ratio-test survivors
};

class FeatureMatchDetector {
 public:
  // `image_size`: the frames' size (the camera's).
  FeatureMatchDetector(const cv::Mat& working_template, cv::Size image_size, const PlanarConfig& config, int min_inliers);
  Detection detect(const cv::Mat& image);
  int template_keypoints() const { return static_cast<int>(keypoints_.size()); }
  NearDetector kind() const { return config_.near_detector; }

 private:
  void describe_template(const cv::Mat& working_template);

  cv::Ptr<cv::Feature2D> frame_features_;
  cv::BFMatcher matcher_;                 // SIFT's (L2); binary descriptors: nearest_two_hamming
  std::vector<cv::KeyPoint> keypoints_;   // the template's
  cv::Mat descriptors_;
  cv::Size template_size_;
  PlanarConfig config_;
  int min_inliers_;
  // Kept between frames.
  cv::Mat scaled_;
  std::vector<cv::KeyPoint> frame_keypoints_;
  cv::Mat frame_descriptors_;
  std::vector<std::vector<cv::DMatch>> knn_;
  std::vector<NearestTwo> nearest_;
  std::vector<cv::Point2f> from_, to_;
  std::vector<unsigned char> mask_;
};

}  // namespace labo::planar
