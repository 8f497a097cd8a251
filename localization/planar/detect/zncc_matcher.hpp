#pragma once
// Zero-mean normalized cross-correlation (OpenCV's TM_CCOEFF_NORMED) of small templates over an
// 8-bit image, computed directly: for each template pixel a row of multiply-adds the compiler
// vectorizes, the window means and energies from integral images. The far detector matches templates
// of 10-50 px over images of at most 320x180 px, where this costs what cv::matchTemplate's DFT does
// (0.25 ms for a 20 px template over 160x90) but allocates nothing: the image's float copy, its
// integrals and the row accumulator are buffers kept between frames.
#include <vector>

#include <opencv2/core.hpp>

namespace labo::planar {

// A template ready for matching: its pixels minus their mean, and their norm.
struct ZnccTemplate {
  ZnccTemplate() = default;
  // `gray`: CV_8UC1, at least 2x2 px.
  explicit ZnccTemplate(const cv::Mat& gray);
  cv::Size size;
  std::vector<float> zero_mean;  // row-major
  double norm = 0;               // sqrt of the sum of squares of zero_mean
};

struct ZnccPeak {
  double score = -1;
  cv::Point at;  // the template's top-left pixel in the image
};

// One image prepared for matching several templates.
class ZnccImage {
 public:
  // Copies `gray` (CV_8UC1) as floats and builds its integrals; buffers keep their memory when the
  // size repeats.
  void assign(const cv::Mat& gray);
  cv::Size size() const { return {pixels_.cols, pixels_.rows}; }

  // The best match of `t` whose top-left pixel lies in `positions` (clipped to where the template
  // fits). A window whose grey levels vary by less than 1 grey level (standard deviation) scores 0:
  // a flat wall correlates with nothing. `row` is scratch kept by the caller.
  ZnccPeak best(const ZnccTemplate& t, cv::Rect positions, std::vector<float>& row) const;

 private:
  cv::Mat pixels_;        // CV_32FC1
  cv::Mat sum_, sqsum_;   // CV_64FC1, (rows + 1) x (cols + 1)
};

}  // namespace labo::planar
