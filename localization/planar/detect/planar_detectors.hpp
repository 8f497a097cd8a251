#pragma once
// The two detectors of the paper's Fig. 3, each giving a first homography (working template px ->
// image px) that the tracker then refines:
//  - TemplateMatchDetector, far away: normalized correlation (TM_CCOEFF_NORMED) of the template over
//    an image pyramid, for object widths from a minimum to a maximum in geometric steps; matching runs
//    where the template is about `detection_match_width_px` wide, so each scale costs little.
//  - SiftDetector, near: SIFT features of the template computed once, Lowe's ratio test, RANSAC
//    homography, found with at least N inliers.
#include <map>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include "localization/planar/planar_config.hpp"

namespace labo::planar {

struct Detection {
  bool found = false;
  cv::Matx33d H = cv::Matx33d::eye();  // working template px -> image px
  double score = 0;                    // best correlation (template) or inlier ratio (SIFT)
  int inliers = 0;                     // SIFT only
  int matches = 0;                     // SIFT only: ratio-test survivors
};

class TemplateMatchDetector {
 public:
  TemplateMatchDetector(const cv::Mat& working_template, const PlanarConfig& config, double min_correlation);
  // Searches object widths in [min_width_px, max_width_px] (image px). `image` is CV_8UC1.
  Detection detect(const cv::Mat& image, double min_width_px, double max_width_px);

 private:
  const cv::Mat& template_at_width(int width_px);

  cv::Mat template_;
  std::map<int, cv::Mat> resized_templates_;  // by width, filled on first use
  cv::Mat resized_image_, result_;            // reused buffers
  PlanarConfig config_;
  double min_correlation_;
};

class SiftDetector {
 public:
  SiftDetector(const cv::Mat& working_template, const PlanarConfig& config, int min_inliers);
  Detection detect(const cv::Mat& image);
  int template_keypoints() const { return static_cast<int>(keypoints_.size()); }

 private:
  cv::Ptr<cv::SIFT> frame_sift_;
  cv::BFMatcher matcher_{cv::NORM_L2};
  std::vector<cv::KeyPoint> keypoints_;
  cv::Mat descriptors_;
  cv::Size template_size_;
  PlanarConfig config_;
  int min_inliers_;
};

}  // namespace labo::planar
