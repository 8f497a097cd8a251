#include "localization/planar/detect/template_detector.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "localization/planar/image_ops.hpp"

namespace labo::planar {

namespace {

constexpr int kMinCoarseHeightPx = 6;  // a thinner template is no longer a pattern
constexpr int kMinLevelSidePx = 16;

// Scale about pixel centres: x' = (x + 0.5) * s - 0.5.
cv::Matx33d centre_scale(double sx, double sy) { return {sx, 0, 0.5 * sx - 0.5, 0, sy, 0.5 * sy - 0.5, 0, 0, 1}; }

cv::Mat resized(const cv::Mat& image, double width_px, double height_px) {
  const cv::Size size(std::max(2, static_cast<int>(std::lround(width_px))), std::max(2, static_cast<int>(std::lround(height_px))));
  cv::Mat out;
  cv::resize(image, out, size, 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace

TemplateMatchDetector::TemplateMatchDetector(const cv::Mat& working_template, cv::Size image_size, const PlanarConfig& config,
                                             double min_correlation)
    : template_(working_template.clone()), config_(config), min_correlation_(min_correlation), image_size_(image_size) {
  if (config_.template_search == TemplateSearch::PerScale) return;
  // The pyramid's levels: down to where the image is still a few templates wide.
  int levels = 1;
  for (cv::Size s = image_size; std::min(s.width, s.height) / 2 >= kMinLevelSidePx; s = {(s.width + 1) / 2, (s.height + 1) / 2}) ++levels;
  const double lo = std::max(8.0, config_.detection_min_width_fraction * image_size.width);
  const double hi = config_.detection_max_width_fraction * image_size.width;
  for (double w = lo; w <= hi * config_.detection_scale_step; w *= config_.detection_scale_step) scales_.push_back(make_scale(w, levels));
  // Buffers of the camera's size, so that the first frame allocates nothing either.
  pyramid_.resize(static_cast<std::size_t>(levels));
  prepared_.resize(static_cast<std::size_t>(levels));
  prepared_valid_.assign(static_cast<std::size_t>(levels), false);
  cv::Size s = image_size;
  for (std::size_t l = 0; l < pyramid_.size(); ++l) {
    const cv::Mat blank(s, CV_8UC1, cv::Scalar(0));
    if (l > 0) pyramid_[l].create(s, CV_8UC1);
    prepared_[l].assign(blank);
    s = {(s.width + 1) / 2, (s.height + 1) / 2};
  }
  pyramid_scratch_.reserve(static_cast<std::size_t>(image_size.width + 8));
  row_.reserve(static_cast<std::size_t>(image_size.width));
}

TemplateMatchDetector::Scale TemplateMatchDetector::make_scale(double width_px, int levels_available) const {
  Scale s;
  s.width_px = width_px;
  const double height_px = width_px * template_.rows / static_cast<double>(template_.cols);
  while (s.coarse_level + 1 < levels_available) {
    const double f = std::ldexp(1.0, -(s.coarse_level + 1));
    if (width_px * f < config_.detection_coarse_width_px || height_px * f < kMinCoarseHeightPx) break;
    ++s.coarse_level;
  }
  s.fine_level = std::max(0, s.coarse_level - 1);
  const double fc = std::ldexp(1.0, -s.coarse_level), ff = std::ldexp(1.0, -s.fine_level);
  const cv::Mat coarse = resized(template_, width_px * fc, height_px * fc);
  const cv::Mat fine = resized(template_, width_px * ff, height_px * ff);
  s.coarse = ZnccTemplate(coarse);
  s.fine = ZnccTemplate(fine);
  s.coarse_size = coarse.size();
  s.fine_size = fine.size();
  return s;
}

Detection TemplateMatchDetector::detect(const cv::Mat& image, double min_width_px, double max_width_px) {
  if (config_.template_search == TemplateSearch::PerScale) return detect_per_scale(image, min_width_px, max_width_px);
  return detect_coarse_to_fine(image, min_width_px, max_width_px);
}

const ZnccImage& TemplateMatchDetector::level(int index) {
  const auto l = static_cast<std::size_t>(index);
  if (!prepared_valid_[l]) {
    if (l > 0) {
      level(index - 1);  // builds the finer levels first
      pyr_down_8u(pyramid_[l - 1], pyramid_[l], pyramid_scratch_);
    }
    prepared_[l].assign(pyramid_[l]);
    prepared_valid_[l] = true;
  }
  return prepared_[l];
}

void TemplateMatchDetector::keep_candidate(const Candidate& c) {
  const double near_px = 0.5 * scales_[static_cast<std::size_t>(c.scale)].width_px;
  // The same place at another width is the same candidate: the better score stands.
  for (int i = 0; i < candidate_count_; ++i) {
    Candidate& k = candidates_[static_cast<std::size_t>(i)];
    const double other_px = 0.5 * scales_[static_cast<std::size_t>(k.scale)].width_px;
    if (cv::norm(k.centre - c.centre) < std::min(near_px, other_px)) {
      if (c.score > k.score) k = c;
      std::sort(candidates_.begin(), candidates_.begin() + candidate_count_, [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
      return;
    }
  }
  const int capacity = std::min(kMaxCandidates, config_.detection_candidates);
  if (candidate_count_ < capacity) {
    candidates_[static_cast<std::size_t>(candidate_count_++)] = c;
  } else if (c.score > candidates_[static_cast<std::size_t>(capacity - 1)].score) {
    candidates_[static_cast<std::size_t>(capacity - 1)] = c;
  } else {
    return;
  }
  std::sort(candidates_.begin(), candidates_.begin() + candidate_count_, [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
}

cv::Matx33d TemplateMatchDetector::homography(cv::Size size, cv::Point at, int level_index) const {
  const double f = std::ldexp(1.0, level_index);
  const cv::Matx33d to_base(f, 0, 0, 0, f, 0, 0, 0, 1);  // pyrDown: level px i is centred on level-0 px 2^L i
  const cv::Matx33d shift(1, 0, at.x, 0, 1, at.y, 0, 0, 1);
  return to_base * shift * centre_scale(static_cast<double>(size.width) / template_.cols, static_cast<double>(size.height) / template_.rows);
}

Detection TemplateMatchDetector::detect_coarse_to_fine(const cv::Mat& image, double min_width_px, double max_width_px) {
  Detection best;
  if (image.type() != CV_8UC1 || scales_.empty()) return best;
  pyramid_[0] = image;
  std::fill(prepared_valid_.begin(), prepared_valid_.end(), false);
  candidate_count_ = 0;
  const double half_step = std::sqrt(config_.detection_scale_step);
  const cv::Rect everywhere(0, 0, image.cols, image.rows);
  for (std::size_t k = 0; k < scales_.size(); ++k) {
    const Scale& s = scales_[k];
    if (s.width_px < min_width_px / half_step || s.width_px > max_width_px * half_step) continue;
    const ZnccPeak p = level(s.coarse_level).best(s.coarse, everywhere, row_);
    if (p.score <= 0) continue;
    const double f = std::ldexp(1.0, s.coarse_level);
    const cv::Point2d centre(f * (p.at.x + 0.5 * (s.coarse_size.width - 1)), f * (p.at.y + 0.5 * (s.coarse_size.height - 1)));
    keep_candidate({p.score, static_cast<int>(k), centre});
  }
  // Each candidate again one level finer, at its width and the two neighbouring ones, within the
  // coarse level's uncertainty.
  for (int i = 0; i < candidate_count_; ++i) {
    const Candidate& c = candidates_[static_cast<std::size_t>(i)];
    const int coarse_level = scales_[static_cast<std::size_t>(c.scale)].coarse_level;
    for (int k = std::max(0, c.scale - 1); k <= std::min(static_cast<int>(scales_.size()) - 1, c.scale + 1); ++k) {
      const Scale& s = scales_[static_cast<std::size_t>(k)];
      const double f = std::ldexp(1.0, -s.fine_level);
      const cv::Point at(static_cast<int>(std::lround(c.centre.x * f - 0.5 * (s.fine_size.width - 1))),
                         static_cast<int>(std::lround(c.centre.y * f - 0.5 * (s.fine_size.height - 1))));
      const int r = (1 << std::max(0, coarse_level - s.fine_level)) + 1;
      const ZnccPeak p = level(s.fine_level).best(s.fine, cv::Rect(at.x - r, at.y - r, 2 * r + 1, 2 * r + 1), row_);
      if (p.score <= best.score) continue;
      best.score = p.score;
      best.H = homography(s.fine_size, p.at, s.fine_level);
    }
  }
  best.found = best.score > min_correlation_;
  return best;
}

const cv::Mat& TemplateMatchDetector::template_at_width(int width_px) {
  auto it = resized_templates_.find(width_px);
  if (it == resized_templates_.end()) {
    const int height = std::max(4, static_cast<int>(std::lround(width_px * template_.rows / double(template_.cols))));
    cv::Mat r;
    cv::resize(template_, r, cv::Size(width_px, height), 0, 0, cv::INTER_AREA);
    it = resized_templates_.emplace(width_px, r).first;
  }
  return it->second;
}

Detection TemplateMatchDetector::detect_per_scale(const cv::Mat& image, double min_width_px, double max_width_px) {
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

}  // namespace labo::planar
