#include "localization/face/face_image_warp.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>

namespace labo::face {

namespace {

constexpr int kSubpixelBits = 5;  // OpenCV's INTER_BITS: positions on a 1/32 px grid
constexpr int kSteps = 1 << kSubpixelBits;

// OpenCV's saturate_cast<int> of a double or float: rounded to nearest, ties to even (the default
// rounding mode), clamped to int.
int round_to_int(double v) {
  if (!(v > INT_MIN)) return std::isnan(v) ? 0 : INT_MIN;
  if (v >= INT_MAX) return INT_MAX;
  return static_cast<int>(std::nearbyint(v));
}

short saturate_short(int v) { return static_cast<short>(std::clamp(v, SHRT_MIN, SHRT_MAX)); }

// The output pixel for a source position given at 1/32 px (X, Y): its top-left neighbour
// (saturated to short, as OpenCV stores it) and the blend of the four neighbours, borders replicated.
uchar sample(const cv::Mat& src, int X, int Y) {
  const int x = saturate_short(X >> kSubpixelBits), y = saturate_short(Y >> kSubpixelBits);
  const int fx = X & (kSteps - 1), fy = Y & (kSteps - 1);
  const int w00 = (kSteps - fx) * (kSteps - fy), w01 = fx * (kSteps - fy), w10 = (kSteps - fx) * fy, w11 = fx * fy;
  int sum;
  if (static_cast<unsigned>(x) < static_cast<unsigned>(src.cols - 1) && static_cast<unsigned>(y) < static_cast<unsigned>(src.rows - 1)) {
    const uchar* p = src.ptr<uchar>(y) + x;
    const std::size_t step = src.step[0];
    sum = w00 * p[0] + w01 * p[1] + w10 * p[step] + w11 * p[step + 1];
  } else {
    const int x0 = std::clamp(x, 0, src.cols - 1), x1 = std::clamp(x + 1, 0, src.cols - 1);
    const uchar* r0 = src.ptr<uchar>(std::clamp(y, 0, src.rows - 1));
    const uchar* r1 = src.ptr<uchar>(std::clamp(y + 1, 0, src.rows - 1));
    sum = w00 * r0[x0] + w01 * r0[x1] + w10 * r1[x0] + w11 * r1[x1];
  }
  return static_cast<uchar>((sum + 512) >> 10);
}

void check_source(const cv::Mat& src, const char* who) {
  if (src.empty() || src.type() != CV_8UC1) throw std::invalid_argument(std::string(who) + ": expected a non-empty 8-bit grey image");
}

}  // namespace

void warp_affine_8u(const cv::Mat& src, const cv::Matx23d& M, cv::Size size, cv::Mat& dst) {
  check_source(src, "warp_affine_8u");
  if (size.width <= 0 || size.height <= 0) throw std::invalid_argument("warp_affine_8u: empty output size");
  if (src.data == dst.data) throw std::invalid_argument("warp_affine_8u: src and dst share their pixels");
  // The inverse map (output pixel -> source pixel), with OpenCV's operations in OpenCV's order.
  double m[6] = {M(0, 0), M(0, 1), M(0, 2), M(1, 0), M(1, 1), M(1, 2)};
  double d = m[0] * m[4] - m[1] * m[3];
  d = d != 0 ? 1. / d : 0;
  const double a11 = m[4] * d, a22 = m[0] * d;
  m[0] = a11;
  m[1] *= -d;
  m[3] *= -d;
  m[4] = a22;
  const double b1 = -m[0] * m[2] - m[1] * m[5];
  const double b2 = -m[3] * m[2] - m[4] * m[5];
  m[2] = b1;
  m[5] = b2;
  // Positions in 1/1024 px: per row the offset, per column the step, each rounded on its own; the
  // sum shifted to 1/32 px after adding half a 1/32 step.
  constexpr int kFineBits = 10;
  constexpr double kFine = 1 << kFineBits;
  constexpr int kHalfStep = (1 << kFineBits) / kSteps / 2;
  dst.create(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    const int X0 = round_to_int((m[1] * y + m[2]) * kFine) + kHalfStep;
    const int Y0 = round_to_int((m[4] * y + m[5]) * kFine) + kHalfStep;
    uchar* out = dst.ptr<uchar>(y);
    for (int x = 0; x < size.width; ++x) {
      const int X = (X0 + round_to_int(m[0] * x * kFine)) >> (kFineBits - kSubpixelBits);
      const int Y = (Y0 + round_to_int(m[3] * x * kFine)) >> (kFineBits - kSubpixelBits);
      out[x] = sample(src, X, Y);
    }
  }
}

void remap_8u(const cv::Mat& src, const cv::Mat& map_x, const cv::Mat& map_y, cv::Mat& dst) {
  check_source(src, "remap_8u");
  if (map_x.type() != CV_32FC1 || map_y.type() != CV_32FC1 || map_x.size() != map_y.size() || map_x.empty()) {
    throw std::invalid_argument("remap_8u: the maps must be two non-empty CV_32FC1 of one size");
  }
  if (src.data == dst.data) throw std::invalid_argument("remap_8u: src and dst share their pixels");
  dst.create(map_x.size(), CV_8UC1);
  for (int y = 0; y < map_x.rows; ++y) {
    const float* mx = map_x.ptr<float>(y);
    const float* my = map_y.ptr<float>(y);
    uchar* out = dst.ptr<uchar>(y);
    // x 32 is exact in float; rounded to the 1/32 px grid as OpenCV converts float maps.
    for (int x = 0; x < map_x.cols; ++x) {
      out[x] = sample(src, round_to_int(mx[x] * static_cast<float>(kSteps)), round_to_int(my[x] * static_cast<float>(kSteps)));
    }
  }
}

cv::Mat& sized_view(cv::Mat& storage, cv::Size size, int type, cv::Mat& view) {
  if (storage.type() != type || storage.cols < size.width || storage.rows < size.height) {
    storage.create(std::max(storage.rows, size.height + size.height / 4), std::max(storage.cols, size.width + size.width / 4), type);
  }
  view = storage(cv::Rect(cv::Point(0, 0), size));
  return view;
}

}  // namespace labo::face
