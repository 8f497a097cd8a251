#include "localization/planar/image_ops.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace labo {

namespace {

// Reflect-101 (OpenCV's default border): -1 -> 1, n -> n - 2.
int reflect_101(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * (n - 1) - i;
  return i;
}

}  // namespace

void pyr_down_8u(const cv::Mat& src, cv::Mat& dst, std::vector<int>& column_sums) {
  if (src.type() != CV_8UC1 || src.empty()) throw std::invalid_argument("pyr_down_8u: src is not a non-empty CV_8UC1 image");
  const int w = src.cols, h = src.rows;
  const int dw = (w + 1) / 2, dh = (h + 1) / 2;
  dst.create(dh, dw, CV_8UC1);
  // Padded by two columns either side, reflected, so the horizontal pass needs no tests.
  column_sums.resize(static_cast<std::size_t>(w + 4));
  int* sums = column_sums.data() + 2;
  for (int y = 0; y < dh; ++y) {
    std::array<const uchar*, 5> rows;
    for (int k = 0; k < 5; ++k) rows[static_cast<std::size_t>(k)] = src.ptr<uchar>(reflect_101(2 * y + k - 2, h));
    const uchar *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3], *r4 = rows[4];
    for (int x = 0; x < w; ++x) sums[x] = r0[x] + 4 * (r1[x] + r3[x]) + 6 * r2[x] + r4[x];
    sums[-1] = sums[reflect_101(-1, w)];
    sums[-2] = sums[reflect_101(-2, w)];
    sums[w] = sums[reflect_101(w, w)];
    sums[w + 1] = sums[reflect_101(w + 1, w)];
    uchar* out = dst.ptr<uchar>(y);
    for (int x = 0; x < dw; ++x) {
      const int* c = sums + 2 * x;
      out[x] = static_cast<uchar>((c[-2] + 4 * (c[-1] + c[1]) + 6 * c[0] + c[2] + 128) >> 8);
    }
  }
}

LinearRemap8u::LinearRemap8u(const cv::Mat& map_x, const cv::Mat& map_y) : size_(map_x.size()) {
  if (map_x.type() != CV_32FC1 || map_y.type() != CV_32FC1 || map_x.size() != map_y.size()) {
    throw std::invalid_argument("LinearRemap8u: the maps must be two CV_32FC1 of one size");
  }
  constexpr int kSteps = 32;  // OpenCV's INTER_TAB_SIZE
  taps_.resize(static_cast<std::size_t>(size_.area()));
  std::size_t i = 0;
  for (int y = 0; y < size_.height; ++y) {
    const float* mx = map_x.ptr<float>(y);
    const float* my = map_y.ptr<float>(y);
    for (int x = 0; x < size_.width; ++x, ++i) {
      // Rounded half to even (the default rounding mode), as cvRound; *32 is exact in float. Clamped
      // as OpenCV's short coordinates are (far outside the frame either way).
      const long X = std::clamp(std::lrint(mx[x] * static_cast<float>(kSteps)), -32768L * kSteps, 32767L * kSteps);
      const long Y = std::clamp(std::lrint(my[x] * static_cast<float>(kSteps)), -32768L * kSteps, 32767L * kSteps);
      Tap& t = taps_[i];
      t.x = static_cast<int>(X >> 5);  // floor: arithmetic shift
      t.y = static_cast<int>(Y >> 5);
      t.fx = static_cast<unsigned short>(X & (kSteps - 1));
      t.fy = static_cast<unsigned short>(Y & (kSteps - 1));
    }
  }
}

void LinearRemap8u::apply(const cv::Mat& src, cv::Mat& dst) const {
  if (src.type() != CV_8UC1 || src.empty()) throw std::invalid_argument("LinearRemap8u: src is not a non-empty CV_8UC1 image");
  if (src.data == dst.data) throw std::invalid_argument("LinearRemap8u: src and dst share their pixels");
  dst.create(size_, CV_8UC1);
  const int w = src.cols, h = src.rows;
  const std::size_t step = src.step[0];
  const auto pixel = [&](int x, int y) -> int {
    return x >= 0 && x < w && y >= 0 && y < h ? src.ptr<uchar>(y)[x] : 0;
  };
  std::size_t i = 0;
  for (int y = 0; y < size_.height; ++y) {
    uchar* out = dst.ptr<uchar>(y);
    for (int x = 0; x < size_.width; ++x, ++i) {
      const Tap& t = taps_[i];
      const int ax = 32 - t.fx, bx = t.fx, ay = 32 - t.fy, by = t.fy;
      int sum;
      if (t.x >= 0 && t.x < w - 1 && t.y >= 0 && t.y < h - 1) {
        const uchar* p = src.data + static_cast<std::size_t>(t.y) * step + static_cast<std::size_t>(t.x);
        sum = ay * (ax * p[0] + bx * p[1]) + by * (ax * p[step] + bx * p[step + 1]);
      } else {
        sum = ay * (ax * pixel(t.x, t.y) + bx * pixel(t.x + 1, t.y)) + by * (ax * pixel(t.x, t.y + 1) + bx * pixel(t.x + 1, t.y + 1));
      }
      // Weights (32 - f) (32 - g) 32 over 2^15: the sum above is over 2^10.
      out[x] = static_cast<uchar>((sum + 512) >> 10);
    }
  }
}

}  // namespace labo
