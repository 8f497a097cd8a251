#include "localization/planar/detect/planar_detectors.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "localization/planar/planar_template.hpp"

namespace labo::planar {

namespace {

// Scale about pixel centres: x' = (x + 0.5) * s - 0.5.
cv::Matx33d centre_scale(double sx, double sy) { return {sx, 0, 0.5 * sx - 0.5, 0, sy, 0.5 * sy - 0.5, 0, 0, 1}; }

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

}  // namespace

TemplateMatchDetector::TemplateMatchDetector(const cv::Mat& working_template, const PlanarConfig& config,
                                             double min_correlation)
    : template_(working_template.clone()), config_(config), min_correlation_(min_correlation) {}

const cv::Mat& TemplateMatchDetector::template_at_width(int width_px) {
  auto it = resized_templates_.find(width_px);
  if (it == resized_templates_.end()) {
    const int height = std::max(4, static_cast<int>(std::lround(width_px * template_.rows / double(template_.cols))));
    cv::Mat resized;
    cv::resize(template_, resized, cv::Size(width_px, height), 0, 0, cv::INTER_AREA);
    it = resized_templates_.emplace(width_px, resized).first;
  }
  return it->second;
}

Detection TemplateMatchDetector::detect(const cv::Mat& image, double min_width_px, double max_width_px) {
  Detection best;
  const int match_width = config_.detection_match_width_px;
  for (double width = std::max(8.0, min_width_px); width <= max_width_px * 1.0001; width *= config_.detection_scale_step) {
    // Match where the template is `match_width` wide (or at full resolution for small objects).
    const int wt = std::max(8, static_cast<int>(std::lround(std::min(width, double(match_width)))));
    const double f = wt / width;
    const cv::Mat& templ = template_at_width(wt);
    const cv::Mat* searched = &image;
    if (f < 1.0) {
      const cv::Size size(std::max(1, static_cast<int>(std::lround(image.cols * f))),
                          std::max(1, static_cast<int>(std::lround(image.rows * f))));
      cv::resize(image, resized_image_, size, 0, 0, cv::INTER_AREA);  // explicit size: exact pixel map
      searched = &resized_image_;
    }
    if (templ.cols >= searched->cols || templ.rows >= searched->rows) continue;
    cv::matchTemplate(*searched, templ, result_, cv::TM_CCOEFF_NORMED);
    double score = 0;
    cv::Point loc;
    cv::minMaxLoc(result_, nullptr, &score, nullptr, &loc);
    if (!std::isfinite(score) || score <= best.score) continue;
    const double fx = static_cast<double>(searched->cols) / image.cols, fy = static_cast<double>(searched->rows) / image.rows;
    const cv::Matx33d shift(1, 0, loc.x, 0, 1, loc.y, 0, 0, 1);
    best.score = score;
    best.H = centre_scale(1 / fx, 1 / fy) * shift *
             centre_scale(static_cast<double>(templ.cols) / template_.cols, static_cast<double>(templ.rows) / template_.rows);
  }
  best.found = best.score > min_correlation_;
  return best;
}

SiftDetector::SiftDetector(const cv::Mat& working_template, const PlanarConfig& config, int min_inliers)
    : frame_sift_(cv::SIFT::create(config.sift_max_frame_features)),
      template_size_(working_template.size()),
      config_(config),
      min_inliers_(min_inliers) {
  cv::SIFT::create()->detectAndCompute(working_template, cv::noArray(), keypoints_, descriptors_);
}

Detection SiftDetector::detect(const cv::Mat& image) {
  Detection d;
  if (keypoints_.size() < 4) return d;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  frame_sift_->detectAndCompute(image, cv::noArray(), keypoints, descriptors);
  if (keypoints.size() < 4) return d;
  std::vector<std::vector<cv::DMatch>> knn;
  matcher_.knnMatch(descriptors_, descriptors, knn, 2);
  std::vector<cv::Point2f> from, to;
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < config_.sift_ratio * m[1].distance) {
      from.push_back(keypoints_[static_cast<std::size_t>(m[0].queryIdx)].pt);
      to.push_back(keypoints[static_cast<std::size_t>(m[0].trainIdx)].pt);
    }
  }
  d.matches = static_cast<int>(from.size());
  if (from.size() < 4) return d;
  std::vector<unsigned char> mask;
  const cv::Mat H = cv::findHomography(from, to, cv::RANSAC, config_.ransac_threshold_px, mask, 2000, 0.995);
  if (H.empty()) return d;
  d.inliers = cv::countNonZero(mask);
  d.score = static_cast<double>(d.inliers) / static_cast<double>(from.size());
  H.convertTo(cv::Mat(3, 3, CV_64F, d.H.val), CV_64F);
  d.found = d.inliers >= min_inliers_ && plausible(d.H, template_size_, 8.0);
  return d;
}

}  // namespace labo::planar
