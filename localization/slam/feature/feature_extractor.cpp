#include "localization/slam/feature/feature_extractor.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace labo::slam {
namespace {
constexpr int kBorder = 20;  // descriptors need a 31x31 patch (rotated): stay clear of the edge
}

FeatureExtractor::FeatureExtractor(const IdealCamera& camera, const ExtractorSettings& settings)
    : camera_(camera), settings_(settings) {
  double s = 1.0;
  for (int l = 0; l < settings_.levels; ++l) {
    scales_.push_back(s);
    s *= settings_.scale;
  }
  pyramid_.resize(static_cast<std::size_t>(settings_.levels));
  // One level: ORB only computes descriptors here, on the level image we hand it.
  orb_ = cv::ORB::create(settings_.max_features, 1.2f, 1, kBorder - 1, 0, 2, cv::ORB::FAST_SCORE, 31,
                         settings_.fast_threshold);
}

void FeatureExtractor::extract(const cv::Mat& gray, FrameFeatures& out) {
  out.clear();
  out_ = &out;
  // Smoothed first: FAST on the raw image fires on sensor noise and on aliased texture, and cv::resize
  // does not filter before decimating, so the levels alias too: smoothed, the corners and their
  // descriptors follow the scene instead of the noise.
  const double sigma = settings_.smoothing_sigma_px;
  if (sigma > 0) {
    const int k = 2 * static_cast<int>(std::ceil(2.5 * sigma)) + 1;  // 7x7 for 1.2
    cv::GaussianBlur(gray, pyramid_[0], cv::Size(k, k), sigma);
  } else {
    pyramid_[0] = gray;
  }
  for (int l = 1; l < settings_.levels; ++l) {
    const cv::Size size(static_cast<int>(std::lround(gray.cols / scales_[static_cast<std::size_t>(l)])),
                        static_cast<int>(std::lround(gray.rows / scales_[static_cast<std::size_t>(l)])));
    cv::resize(pyramid_[static_cast<std::size_t>(l - 1)], pyramid_[static_cast<std::size_t>(l)], size, 0, 0,
               cv::INTER_LINEAR);
  }
  // Budget per level proportional to its area, as a uniform density of features over scale space.
  double total = 0;
  for (double s : scales_) total += 1.0 / (s * s);
  for (int l = 0; l < settings_.levels; ++l) {
    const double share = 1.0 / (scales_[static_cast<std::size_t>(l)] * scales_[static_cast<std::size_t>(l)]) / total;
    detect_level(l, static_cast<int>(settings_.max_features * share));
  }
}

void FeatureExtractor::detect_level(int level, int budget) {
  const cv::Mat& img = pyramid_[static_cast<std::size_t>(level)];
  if (img.cols <= 2 * kBorder || img.rows <= 2 * kBorder || budget <= 0) return;
  const int cell = settings_.cell_px;
  const int cols = (img.cols + cell - 1) / cell, rows = (img.rows + cell - 1) / cell;
  const int per_cell = std::max(2, (budget + cols * rows - 1) / (cols * rows));
  cell_count_.assign(static_cast<std::size_t>(cols * rows), 0);
  kept_.clear();
  for (int pass = 0; pass < 2; ++pass) {
    const int threshold = pass == 0 ? settings_.fast_threshold : settings_.fast_threshold_low;
    cv::FAST(img, raw_, threshold, true);
    std::sort(raw_.begin(), raw_.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
    for (const cv::KeyPoint& k : raw_) {
      if (k.pt.x < kBorder || k.pt.y < kBorder || k.pt.x >= img.cols - kBorder || k.pt.y >= img.rows - kBorder) continue;
      const std::size_t c = static_cast<std::size_t>(static_cast<int>(k.pt.y) / cell * cols + static_cast<int>(k.pt.x) / cell);
      // cell_count_ < 0 marks cells the first pass filled: the low-threshold pass skips them.
      if (cell_count_[c] < 0 || cell_count_[c] >= per_cell) continue;
      ++cell_count_[c];
      kept_.push_back(k);
    }
    if (static_cast<int>(kept_.size()) >= budget / 2) break;
    for (int& n : cell_count_) n = n > 0 ? -1 : 0;
  }
  if (kept_.size() > static_cast<std::size_t>(budget) * 2) kept_.resize(static_cast<std::size_t>(budget) * 2);
  for (cv::KeyPoint& k : kept_) {
    k.octave = 0;
    k.angle = 0;  // no rotation invariance: the drone barely rolls, and fixed patterns match better
  }
  orb_->compute(img, kept_, descriptors_);
  // The level's true size ratios, not the nominal scale: the sizes are rounded (640 / 1.5^3 = 189.6
  // -> 190), and cv::resize maps by the size ratio. With the nominal scale, coordinates on levels 1-3
  // would be off by up to 0.3 % of their distance to the image's corner (a rotation seen on level 3
  // 0.3 % too large, on level 2 0.3 % too small; tests/localization/slam/feature_geometry_test.cpp).
  const double sx = static_cast<double>(pyramid_[0].cols) / img.cols, sy = static_cast<double>(pyramid_[0].rows) / img.rows;
  for (int i = 0; i < static_cast<int>(kept_.size()); ++i) {
    const cv::KeyPoint& k = kept_[static_cast<std::size_t>(i)];
    Feature f;
    // Level pixel centres to level-0 pixel centres.
    const double u = (k.pt.x + 0.5) * sx - 0.5, v = (k.pt.y + 0.5) * sy - 0.5;
    f.image_px = Eigen::Vector2f(static_cast<float>(u), static_cast<float>(v));
    f.px = camera_.ideal_from_image(u, v);
    f.level = level;
    f.response = k.response;
    Descriptor d;
    std::copy_n(descriptors_.ptr<std::uint8_t>(i), 32, d.begin());
    out_->features.push_back(f);
    out_->descriptors.push_back(d);
  }
}

}  // namespace labo::slam
