#pragma once
// Allocation-free replacements, bit-identical to OpenCV 4.6, for the OpenCV image calls the planar
// localizer makes on every tracked frame: each of those allocates scratch buffers inside OpenCV on
// every call (cv::pyrDown 1-2 row buffers, cv::remap its per-stripe blocks). The results are integer
// arithmetic, so "the same" is exact: tests/localization/planar/image_ops_test.cpp compares them
// pixel for pixel with OpenCV's on random images.
#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace labo::planar {

// cv::pyrDown(src, dst) for CV_8UC1 with the default border (reflect-101): the 5x5 binomial
// [1 4 6 4 1]^2 / 256 at every other pixel, rounded half up; dst is ((cols + 1) / 2, (rows + 1) / 2).
// `column_sums` is scratch (kept by the caller, so that steady state allocates nothing: dst keeps
// its buffer when its size and type already match).
void pyr_down_8u(const cv::Mat& src, cv::Mat& dst, std::vector<int>& column_sums);

// cv::remap(src, dst, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0) for CV_8UC1 frames with
// fixed CV_32FC1 maps, the maps' work done once: OpenCV rounds each map coordinate to 1/32 px
// (half to even) and blends the four neighbours with integer weights (32 - fx or fx) (32 - fy or fy)
// * 32 summing to 2^15, rounded half up; a neighbour outside the frame counts as 0. The same here,
// with the rounded positions precomputed (OpenCV converts the float maps again on every call).
class LinearRemap8u {
 public:
  LinearRemap8u() = default;
  // map_x, map_y: CV_32FC1 of the output's size, the source pixel each output pixel samples, in a
  // source image of `source_size`.
  LinearRemap8u(const cv::Mat& map_x, const cv::Mat& map_y, cv::Size source_size);
  bool empty() const { return taps_.empty(); }
  // src: CV_8UC1 of the source size. dst: the output's size, CV_8UC1 (reallocated only when it
  // differs). src must not be dst.
  void apply(const cv::Mat& src, cv::Mat& dst) const;

 private:
  struct Tap {
    int x, y;                   // the top-left neighbour (floor of the position at 1/32 px)
    std::array<short, 4> w;     // its and its right, lower, lower-right neighbours' weights, over 2^10
    bool interior;              // all four neighbours inside the source
  };
  cv::Size size_, source_size_;
  std::vector<Tap> taps_;  // row-major over the output
};

// cv::GaussianBlur(image(roi), dst(roi), cv::Size(0, 0), sigma) for CV_8UC1 and a region of interest
// smaller than the image, which allocates its filter engine, kernels and ring buffer on every call.
// For such a region OpenCV 4.6 filters in float (its bit-exact fixed-point path is only for whole
// images): the float kernel of size round(6 sigma + 1) | 1, rows then columns, every multiply-add
// fused as its SIMD code does on FMA hardware (AVX2, AVX-512), rounded to nearest. The same
// operations in the same order here, so the pixels are OpenCV's on such machines. Pixels outside
// `roi` are the image's own, reflected (101) at the image's border, as for an OpenCV region of interest.
class GaussianBlur8u {
 public:
  GaussianBlur8u() = default;
  explicit GaussianBlur8u(double sigma);
  // dst: the image's size and type (created if not); only its `roi` is written. `scratch`: kept by
  // the caller. Not for roi == the whole image (OpenCV blurs that differently).
  void apply(const cv::Mat& image, cv::Rect roi, cv::Mat& dst, std::vector<float>& scratch) const;

 private:
  std::vector<float> kernel_;  // 2 r + 1 taps
};

}  // namespace labo::planar
