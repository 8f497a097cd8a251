#include "localization/planar/track/ecc_tracker.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "localization/planar/planar_template.hpp"

namespace labo::planar {

namespace {

// Maps template pixels of pyramid level `level` to level-0 pixels. cv::pyrDown keeps every other
// pixel (level-1 pixel i is centred on level-0 pixel 2i), so the map is a pure scale.
cv::Matx33d level_to_base(int level) {
  const double s = std::ldexp(1.0, level);
  return {s, 0, 0, 0, s, 0, 0, 0, 1};
}

cv::Matx33d translation(double x, double y) { return {1, 0, x, 0, 1, y, 0, 0, 1}; }

}  // namespace

int matching_template_level(const cv::Matx33d& H, cv::Size template_size, int max_level) {
  const double w = template_size.width - 0.5, h = template_size.height - 0.5;
  const std::array<cv::Point2d, 4> c = map_corners(H, {cv::Point2d(-0.5, -0.5), cv::Point2d(w, -0.5),
                                                       cv::Point2d(w, h), cv::Point2d(-0.5, h)});
  // Shoelace area of the quadrilateral against the template's area.
  double area = 0;
  for (int i = 0; i < 4; ++i) area += c[i].x * c[(i + 1) % 4].y - c[(i + 1) % 4].x * c[i].y;
  const double ratio = std::sqrt(std::abs(area) / 2.0 / (static_cast<double>(template_size.area())));
  if (!std::isfinite(ratio) || ratio <= 0) return 0;
  const int level = static_cast<int>(std::floor(std::log2(1.0 / ratio) + 0.3));
  return std::clamp(level, 0, max_level);
}

EccTracker::EccTracker(const cv::Mat& template_gray, const PlanarConfig& config) : config_(config) {
  cv::Mat level;
  template_gray.convertTo(level, CV_32F);
  template_levels_.push_back(level);
  while (std::min(template_levels_.back().cols, template_levels_.back().rows) >= 64) {
    cv::Mat next;
    cv::pyrDown(template_levels_.back(), next);
    template_levels_.push_back(next);
  }
}

HomographyTrackOutcome EccTracker::track(const cv::Mat& image, const cv::Matx33d& H_prior) {
  HomographyTrackOutcome out;
  out.H = H_prior;
  const int level = matching_template_level(H_prior, template_levels_[0].size(),
                                            static_cast<int>(template_levels_.size()) - 1);
  const cv::Mat& templ = template_levels_[level];
  const cv::Matx33d U = level_to_base(level);
  const cv::Matx33d H_level = H_prior * U;

  // Crop around the predicted quadrilateral, with a margin for the motion since the prior.
  const double w = templ.cols - 0.5, h = templ.rows - 0.5;
  const auto c = map_corners(H_level, {cv::Point2d(-0.5, -0.5), cv::Point2d(w, -0.5), cv::Point2d(w, h),
                                       cv::Point2d(-0.5, h)});
  double x0 = c[0].x, x1 = c[0].x, y0 = c[0].y, y1 = c[0].y;
  for (const auto& p : c) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  if (!std::isfinite(x0 + x1 + y0 + y1)) {
    out.failure = "degenerate prior";
    return out;
  }
  const double margin = std::max(24.0, 0.25 * std::max(x1 - x0, y1 - y0));
  const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(std::floor(std::max(-1e6, x0 - margin))),
                                          static_cast<int>(std::floor(std::max(-1e6, y0 - margin)))),
                                cv::Point(static_cast<int>(std::ceil(std::min(1e6, x1 + margin))),
                                          static_cast<int>(std::ceil(std::min(1e6, y1 + margin))))) &
                       cv::Rect(0, 0, image.cols, image.rows);
  if (roi.width < 16 || roi.height < 16) {
    out.failure = "object out of view";
    return out;
  }
  cv::Matx33d warp_d = translation(-roi.x, -roi.y) * H_level;
  warp_d *= 1.0 / warp_d(2, 2);
  cv::Mat warp;
  cv::Mat(warp_d).convertTo(warp, CV_32F);
  image(roi).convertTo(roi_float_, CV_32F);  // ECC wants both images of one type
  try {
    const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, config_.ecc_max_iterations,
                                    config_.ecc_epsilon);
    out.correlation = cv::findTransformECC(templ, roi_float_, warp, cv::MOTION_HOMOGRAPHY, criteria, cv::noArray(),
                                           config_.ecc_gauss_size);
  } catch (const cv::Exception&) {
    out.failure = "ECC did not converge";
    return out;
  }
  cv::Matx33d result;
  cv::Mat(warp).convertTo(cv::Mat(3, 3, CV_64F, result.val), CV_64F);
  out.H = translation(roi.x, roi.y) * result * U.inv();
  out.H *= 1.0 / out.H(2, 2);
  out.iterations = 0;  // OpenCV does not report the count
  if (!std::isfinite(out.correlation) || !cv::checkRange(cv::Mat(out.H))) {
    out.failure = "ECC returned non-finite values";
    return out;
  }
  out.converged = true;
  return out;
}

}  // namespace labo::planar
