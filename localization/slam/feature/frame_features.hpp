#pragma once
// The features of one frame: FAST corners on a 4-level pyramid, spread over the image by a grid,
// each with a 256-bit binary descriptor (OpenCV's ORB/rBRIEF computed at the corner's own level) and
// its position in ideal (undistorted) level-0 pixels.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace labo::slam {

using Descriptor = std::array<std::uint8_t, 32>;

inline int hamming(const Descriptor& a, const Descriptor& b) {
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    __builtin_memcpy(&x, a.data() + i, 8);
    __builtin_memcpy(&y, b.data() + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

struct Feature {
  Eigen::Vector2d px;        // ideal level-0 pixel
  Eigen::Vector2f image_px;  // distorted level-0 pixel (drawing, debugging)
  int level = 0;
  float response = 0;
};

struct FrameFeatures {
  std::vector<Feature> features;
  std::vector<Descriptor> descriptors;
  std::size_t size() const { return features.size(); }
  void clear() {
    features.clear();
    descriptors.clear();
  }
};

// Uniform grid over ideal pixels for radius queries (features of one frame).
class FeatureGrid {
 public:
  FeatureGrid(const Eigen::Vector2d& min, const Eigen::Vector2d& max, double cell_px);
  void build(const FrameFeatures& frame);
  // Indices of features within `radius` of `px` whose level is in [min_level, max_level];
  // `out` is cleared first (its capacity is kept).
  void query(const Eigen::Vector2d& px, double radius, int min_level, int max_level,
             const FrameFeatures& frame, std::vector<int>& out) const;

 private:
  Eigen::Vector2d min_;
  double cell_;
  int cols_, rows_;
  std::vector<std::vector<int>> cells_;
};

}  // namespace labo::slam
