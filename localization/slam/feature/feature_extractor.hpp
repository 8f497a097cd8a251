#pragma once
// FeatureExtractor: the per-frame front end. Smooths the frame (Gaussian, by default sigma 1.2 px),
// builds the pyramid (levels of 1, 1/s, 1/s^2, 1/s^3),
// runs FAST on every level, keeps the strongest corners per grid cell so that features cover the
// image (a flat cell retries with a lower threshold), and computes binary descriptors at each
// corner's level. Buffers are reused from frame to frame.
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/feature/frame_features.hpp"

namespace labo::slam {

struct ExtractorSettings {
  int levels = 4;
  double scale = 1.5;
  int max_features = 1000;
  int fast_threshold = 20;
  int fast_threshold_low = 7;
  int cell_px = 40;  // grid cell at each level
  double smoothing_sigma_px = 1.2;  // Gaussian smoothing of the frame before FAST; 0: none
};

class FeatureExtractor {
 public:
  FeatureExtractor(const IdealCamera& camera, const ExtractorSettings& settings);
  // gray: 8-bit, the camera's size (checked by the caller).
  void extract(const cv::Mat& gray, FrameFeatures& out);
  const std::vector<cv::Mat>& pyramid() const { return pyramid_; }
  double level_scale(int level) const { return scales_[static_cast<std::size_t>(level)]; }
  int levels() const { return settings_.levels; }

 private:
  void detect_level(int level, int budget);

  const IdealCamera& camera_;
  ExtractorSettings settings_;
  std::vector<double> scales_;
  std::vector<cv::Mat> pyramid_;
  std::vector<cv::KeyPoint> raw_, kept_;
  std::vector<int> cell_count_;
  cv::Mat descriptors_;
  cv::Ptr<cv::ORB> orb_;
  FrameFeatures* out_ = nullptr;
};

}  // namespace labo::slam
