#include "localization/planar/detect/planar_detectors.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/planar/detect/binary_matcher.hpp"
#include "localization/planar/planar_template.hpp"

namespace labo::planar {

namespace {

// The template's features cover object sizes down to this fraction of the working template (320 px:
// 43 px, the oscilloscope at 5 m): ORB's 8 levels 1.2 apart reach only 1/3.6, which missed the panel
// at 2.5 m partly in view ("planar: a panel sliding slowly across the image's edge ..."); the frame
// keeps the detector's own levels (objects larger than the template).
constexpr int kTemplateOrbLevels = 12;
// Binary detectors drop keypoints within their patch (ORB: 31 px) of the border on every pyramid
// level; the template is padded with its mean grey by that patch at the coarsest level (31 x 1.2^11 px
// at level 0) so that its edges keep their features at every scale.
constexpr int kBinaryTemplatePaddingPx = 230;
constexpr int kTemplateFeatures = 1000;
constexpr int kFrameEdgePx = 8;

// A convex quadrilateral of reasonable size: a homography a real plane can produce.
bool plausible(const cv::Matx33d& H, cv::Size template_size, double min_side_px) {
  const double w = template_size.width - 0.5, h = template_size.height - 0.5;
  const auto c = map_corners(H, {cv::Point2d(-0.5, -0.5), cv::Point2d(w, -0.5), cv::Point2d(w, h), cv::Point2d(-0.5, h)});
  double sign = 0;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d a = c[(i + 1) % 4] - c[i], b = c[(i + 2) % 4] - c[(i + 1) % 4];
    if (!std::isfinite(a.x + a.y) || cv::norm(a) < min_side_px) return false;
    const double cross = a.x * b.y - a.y * b.x;
    if (sign == 0) sign = cross;
    if (cross == 0 || (cross > 0) != (sign > 0)) return false;
  }
  return true;
}

cv::Ptr<cv::Feature2D> make_features(NearDetector kind, int max_features) {
  switch (kind) {
    case NearDetector::Sift: return cv::SIFT::create(max_features);
    // Keypoints up to kFrameEdgePx from the frame's border (ORB's default is its 31 px patch): a panel
    // entering the view shows there first. Their descriptors read ORB's own reflected border.
    case NearDetector::Orb: return cv::ORB::create(max_features, 1.2f, 8, kFrameEdgePx);
    case NearDetector::Brisk: return cv::BRISK::create();
    case NearDetector::Akaze: return cv::AKAZE::create();
  }
  return cv::SIFT::create(max_features);
}

// A frame of `size` with the template in its middle, half the frame wide, on its mean grey: what the
// constructor runs the detector on once.
cv::Mat warm_up_frame(const cv::Mat& working_template, cv::Size size) {
  cv::Mat frame(size, CV_8UC1, cv::Scalar(cv::mean(working_template)[0]));
  const double s = std::min(0.5 * size.width / working_template.cols, 0.8 * size.height / working_template.rows);
  const cv::Size placed(std::max(1, static_cast<int>(working_template.cols * s)), std::max(1, static_cast<int>(working_template.rows * s)));
  cv::Mat inner = frame(cv::Rect((size.width - placed.width) / 2, (size.height - placed.height) / 2, placed.width, placed.height));
  cv::resize(working_template, inner, placed, 0, 0, cv::INTER_AREA);
  return frame;
}

}  // namespace

FeatureMatchDetector::FeatureMatchDetector(const cv::Mat& working_template, cv::Size image_size, const PlanarConfig& config,
                                           int min_inliers)
    : frame_features_(make_features(config.near_detector, config.near_max_frame_features)),
      matcher_(config.near_detector == NearDetector::Sift ? cv::NORM_L2 : cv::NORM_HAMMING),
      template_size_(working_template.size()),
      config_(config),
      min_inliers_(min_inliers) {
  describe_template(working_template);
  if (image_size.width >= 32 && image_size.height >= 32) detect(warm_up_frame(working_template, image_size));
}

void FeatureMatchDetector::describe_template(const cv::Mat& working_template) {
  if (config_.near_detector == NearDetector::Sift) {
    cv::SIFT::create()->detectAndCompute(working_template, cv::noArray(), keypoints_, descriptors_);
    return;
  }
  const int pad = kBinaryTemplatePaddingPx;
  cv::Mat padded;
  cv::copyMakeBorder(working_template, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(cv::mean(working_template)[0]));
  std::vector<cv::KeyPoint> all;
  cv::Mat all_descriptors;
  const cv::Ptr<cv::Feature2D> features = config_.near_detector == NearDetector::Orb
                                               ? cv::Ptr<cv::Feature2D>(cv::ORB::create(kTemplateFeatures, 1.2f, kTemplateOrbLevels))
                                               : make_features(config_.near_detector, kTemplateFeatures);
  features->detectAndCompute(padded, cv::noArray(), all, all_descriptors);
  for (std::size_t i = 0; i < all.size(); ++i) {
    cv::KeyPoint k = all[i];
    k.pt -= cv::Point2f(pad, pad);
    if (k.pt.x < 0 || k.pt.y < 0 || k.pt.x > working_template.cols - 1 || k.pt.y > working_template.rows - 1) continue;
    keypoints_.push_back(k);
    descriptors_.push_back(all_descriptors.row(static_cast<int>(i)));
  }
}

Detection FeatureMatchDetector::detect(const cv::Mat& image) {
  Detection d;
  if (keypoints_.size() < 4) return d;
  const cv::Mat* searched = &image;
  if (config_.near_frame_scale < 1.0) {
    const cv::Size size(std::max(1, static_cast<int>(std::lround(image.cols * config_.near_frame_scale))),
                        std::max(1, static_cast<int>(std::lround(image.rows * config_.near_frame_scale))));
    cv::resize(image, scaled_, size, 0, 0, cv::INTER_AREA);
    searched = &scaled_;
  }
  frame_features_->detectAndCompute(*searched, cv::noArray(), frame_keypoints_, frame_descriptors_);
  if (frame_keypoints_.size() < 4) return d;
  // Area-resize pixel map back to the frame: x = (x' + 0.5) / s - 0.5.
  const float sx = static_cast<float>(image.cols) / searched->cols, sy = static_cast<float>(image.rows) / searched->rows;
  from_.clear();
  to_.clear();
  const auto keep = [&](int template_index, int frame_index) {
    const cv::Point2f p = frame_keypoints_[static_cast<std::size_t>(frame_index)].pt;
    from_.push_back(keypoints_[static_cast<std::size_t>(template_index)].pt);
    to_.emplace_back((p.x + 0.5f) * sx - 0.5f, (p.y + 0.5f) * sy - 0.5f);
  };
  if (config_.near_detector == NearDetector::Sift) {
    knn_.clear();  // OpenCV's knnMatch appends to what the vector holds
    matcher_.knnMatch(descriptors_, frame_descriptors_, knn_, 2);
    for (const auto& m : knn_) {
      if (m.size() == 2 && m[0].distance < config_.near_ratio * m[1].distance) keep(m[0].queryIdx, m[0].trainIdx);
    }
  } else {
    nearest_two_hamming(descriptors_, frame_descriptors_, nearest_);
    for (std::size_t i = 0; i < nearest_.size(); ++i) {
      const NearestTwo& n = nearest_[i];
      if (n.best >= 0 && n.best_distance < config_.near_ratio * n.second_distance) keep(static_cast<int>(i), n.best);
    }
  }
  d.matches = static_cast<int>(from_.size());
  if (from_.size() < 4) return d;
  const cv::Mat H = cv::findHomography(from_, to_, cv::RANSAC, config_.ransac_threshold_px, mask_, 2000, 0.995);
  if (H.empty()) return d;
  d.inliers = cv::countNonZero(mask_);
  d.score = static_cast<double>(d.inliers) / static_cast<double>(from_.size());
  H.convertTo(cv::Mat(3, 3, CV_64F, d.H.val), CV_64F);
  d.found = d.inliers >= min_inliers_ && plausible(d.H, template_size_, 8.0);
  return d;
}

}  // namespace labo::planar
