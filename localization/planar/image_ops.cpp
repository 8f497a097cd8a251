#include "localization/planar/image_ops.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace labo::planar {

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

LinearRemap8u::LinearRemap8u(const cv::Mat& map_x, const cv::Mat& map_y, cv::Size source_size)
    : size_(map_x.size()), source_size_(source_size) {
  if (map_x.type() != CV_32FC1 || map_y.type() != CV_32FC1 || map_x.size() != map_y.size()) {
    throw std::invalid_argument("LinearRemap8u: the maps must be two CV_32FC1 of one size");
  }
  if (source_size.width < 2 || source_size.height < 2) throw std::invalid_argument("LinearRemap8u: source smaller than 2x2");
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
      const int fx = static_cast<int>(X & (kSteps - 1)), fy = static_cast<int>(Y & (kSteps - 1));
      // The weights over 2^10 (OpenCV's are these times 32, over 2^15).
      t.w = {static_cast<short>((32 - fx) * (32 - fy)), static_cast<short>(fx * (32 - fy)), static_cast<short>((32 - fx) * fy),
             static_cast<short>(fx * fy)};
      t.interior = t.x >= 0 && t.x < source_size.width - 1 && t.y >= 0 && t.y < source_size.height - 1;
    }
  }
}

void LinearRemap8u::apply(const cv::Mat& src, cv::Mat& dst) const {
  if (src.type() != CV_8UC1 || src.size() != source_size_) throw std::invalid_argument("LinearRemap8u: src is not a CV_8UC1 image of the source size");
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
      int sum;
      if (t.interior) {
        const uchar* p = src.data + static_cast<std::size_t>(t.y) * step + static_cast<std::size_t>(t.x);
        sum = t.w[0] * p[0] + t.w[1] * p[1] + t.w[2] * p[step] + t.w[3] * p[step + 1];
      } else {
        sum = t.w[0] * pixel(t.x, t.y) + t.w[1] * pixel(t.x + 1, t.y) + t.w[2] * pixel(t.x, t.y + 1) + t.w[3] * pixel(t.x + 1, t.y + 1);
      }
      out[x] = static_cast<uchar>((sum + 512) >> 10);
    }
  }
}

GaussianBlur8u::GaussianBlur8u(double sigma) {
  if (!(sigma > 0)) throw std::invalid_argument("GaussianBlur8u: sigma must be positive");
  const int size = cvRound(sigma * 3 * 2 + 1) | 1;  // OpenCV's kernel size for 8-bit images
  const cv::Mat g = cv::getGaussianKernel(size, sigma, CV_32F);
  kernel_.assign(g.ptr<float>(), g.ptr<float>() + size);
}

namespace {

// The two passes, with OpenCV's operations in OpenCV's order: every multiply-add fused (its SIMD
// muladd with FMA), each row pixel summed tap by tap from the left, each column pixel from the centre
// outwards with each symmetric pair added first. Loops run over pixels innermost so that they
// vectorize; cloned for FMA hardware (vfmadd, AVX vectors) and a default (std::fma from the library: as exact,
// slower).
__attribute__((target_clones("fma", "default")))
void gaussian_row(const float* line, int cols, const float* kernel, int taps, float* out) {
  for (int x = 0; x < cols; ++x) out[x] = 0.0f;
  for (int t = 0; t < taps; ++t) {
    const float k = kernel[t];
    const float* in = line + t;
    for (int x = 0; x < cols; ++x) out[x] = std::fma(in[x], k, out[x]);
  }
}

__attribute__((target_clones("fma", "default")))
void gaussian_column(const float* centre, std::size_t stride, int cols, const float* kernel, int r, float* sum, uchar* out) {
  const float k0 = kernel[r];
  for (int x = 0; x < cols; ++x) sum[x] = centre[x] * k0;
  for (int d = 1; d <= r; ++d) {
    const float k = kernel[r + d];
    const float* below = centre + static_cast<std::size_t>(d) * stride;
    const float* above = centre - static_cast<std::size_t>(d) * stride;
    for (int x = 0; x < cols; ++x) sum[x] = std::fma(below[x] + above[x], k, sum[x]);
  }
  // To nearest, ties to even (cv::saturate_cast): adding and subtracting 1.5 * 2^23 rounds a float
  // below 2^22 in the default rounding mode; the sums are >= 0 (a positive kernel).
  constexpr float kRound = 12582912.0f;
  for (int x = 0; x < cols; ++x) {
    const float rounded = std::min((sum[x] + kRound) - kRound, 255.0f);
    out[x] = static_cast<uchar>(static_cast<int>(rounded));
  }
}

}  // namespace

void GaussianBlur8u::apply(const cv::Mat& image, cv::Rect roi, cv::Mat& dst, std::vector<float>& scratch) const {
  if (image.type() != CV_8UC1 || image.empty()) throw std::invalid_argument("GaussianBlur8u: image is not a non-empty CV_8UC1 image");
  if (image.data == dst.data) throw std::invalid_argument("GaussianBlur8u: image and dst share their pixels");
  dst.create(image.size(), CV_8UC1);
  roi &= cv::Rect(0, 0, image.cols, image.rows);
  if (roi.area() == 0) return;
  const int taps = static_cast<int>(kernel_.size()), r = taps / 2;
  const int rows = roi.height + 2 * r, cols = roi.width;
  const std::size_t stride = static_cast<std::size_t>(cols);
  // Row sums of every image row the blur reads, then one line of the row's pixels (float, reflected
  // at the image's border), then one row of column sums.
  scratch.resize(static_cast<std::size_t>(rows) * stride + (stride + static_cast<std::size_t>(2 * r)) + stride);
  float* row_sums = scratch.data();
  float* line = row_sums + static_cast<std::size_t>(rows) * stride;
  float* column_sums = line + stride + static_cast<std::size_t>(2 * r);
  for (int j = 0; j < rows; ++j) {
    const uchar* src = image.ptr<uchar>(reflect_101(roi.y - r + j, image.rows));
    // Reflected only where the line passes the image's border.
    const int first = std::max(0, r - roi.x), last = std::min(cols + 2 * r, image.cols - roi.x + r);
    for (int i = 0; i < first; ++i) line[i] = static_cast<float>(src[reflect_101(roi.x - r + i, image.cols)]);
    const uchar* inside = src + (roi.x - r);
    for (int i = first; i < last; ++i) line[i] = static_cast<float>(inside[i]);
    for (int i = std::max(first, last); i < cols + 2 * r; ++i) line[i] = static_cast<float>(src[reflect_101(roi.x - r + i, image.cols)]);
    gaussian_row(line, cols, kernel_.data(), taps, row_sums + static_cast<std::size_t>(j) * stride);
  }
  for (int y = 0; y < roi.height; ++y) {
    gaussian_column(row_sums + static_cast<std::size_t>(y + r) * stride, stride, cols, kernel_.data(), r, column_sums,
                    dst.ptr<uchar>(roi.y + y) + roi.x);
  }
}

}  // namespace labo::planar
