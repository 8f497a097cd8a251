#include "localization/planar/detect/zncc_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace labo::planar {

namespace {
constexpr double kMinWindowVariance = 1.0;  // grey levels squared
}  // namespace

ZnccTemplate::ZnccTemplate(const cv::Mat& gray) : size(gray.size()) {
  if (gray.type() != CV_8UC1 || gray.cols < 2 || gray.rows < 2) {
    throw std::invalid_argument("ZnccTemplate: the template must be CV_8UC1 and at least 2x2 px");
  }
  const double mean = cv::mean(gray)[0];
  zero_mean.reserve(static_cast<std::size_t>(gray.total()));
  double squares = 0;
  for (int y = 0; y < gray.rows; ++y) {
    const unsigned char* row = gray.ptr<unsigned char>(y);
    for (int x = 0; x < gray.cols; ++x) {
      const double v = row[x] - mean;
      zero_mean.push_back(static_cast<float>(v));
      squares += v * v;
    }
  }
  norm = std::sqrt(squares);
}

void ZnccImage::assign(const cv::Mat& gray) {
  if (gray.type() != CV_8UC1) throw std::invalid_argument("ZnccImage: the image must be CV_8UC1");
  pixels_.create(gray.rows, gray.cols, CV_32FC1);
  sum_.create(gray.rows + 1, gray.cols + 1, CV_64FC1);
  sqsum_.create(gray.rows + 1, gray.cols + 1, CV_64FC1);
  std::fill_n(sum_.ptr<double>(0), sum_.cols, 0.0);
  std::fill_n(sqsum_.ptr<double>(0), sqsum_.cols, 0.0);
  for (int y = 0; y < gray.rows; ++y) {
    const unsigned char* in = gray.ptr<unsigned char>(y);
    float* out = pixels_.ptr<float>(y);
    const double* s_above = sum_.ptr<double>(y);
    const double* q_above = sqsum_.ptr<double>(y);
    double* s = sum_.ptr<double>(y + 1);
    double* q = sqsum_.ptr<double>(y + 1);
    s[0] = q[0] = 0;
    double row_sum = 0, row_sq = 0;
    for (int x = 0; x < gray.cols; ++x) {
      const double v = in[x];
      out[x] = static_cast<float>(v);
      row_sum += v;
      row_sq += v * v;
      s[x + 1] = s_above[x + 1] + row_sum;
      q[x + 1] = q_above[x + 1] + row_sq;
    }
  }
}

ZnccPeak ZnccImage::best(const ZnccTemplate& t, cv::Rect positions, std::vector<float>& row) const {
  ZnccPeak peak;
  const cv::Rect fits(0, 0, pixels_.cols - t.size.width + 1, pixels_.rows - t.size.height + 1);
  positions &= fits;
  if (positions.empty() || !(t.norm > 0)) return peak;
  const int n = positions.width;
  row.resize(static_cast<std::size_t>(n));
  const double area = static_cast<double>(t.size.area());
  for (int y = positions.y; y < positions.y + positions.height; ++y) {
    std::fill(row.begin(), row.end(), 0.0f);
    float* acc = row.data();
    const float* tv = t.zero_mean.data();
    for (int i = 0; i < t.size.height; ++i) {
      const float* image_row = pixels_.ptr<float>(y + i) + positions.x;
      for (int j = 0; j < t.size.width; ++j, ++tv) {
        const float w = *tv;
        const float* src = image_row + j;
        for (int x = 0; x < n; ++x) acc[x] += w * src[x];
      }
    }
    const double* s0 = sum_.ptr<double>(y);
    const double* s1 = sum_.ptr<double>(y + t.size.height);
    const double* q0 = sqsum_.ptr<double>(y);
    const double* q1 = sqsum_.ptr<double>(y + t.size.height);
    for (int x = 0; x < n; ++x) {
      const int a = positions.x + x, b = a + t.size.width;
      const double sum = s1[b] - s1[a] - s0[b] + s0[a];
      const double energy = (q1[b] - q1[a] - q0[b] + q0[a]) - sum * sum / area;
      if (!(energy > kMinWindowVariance * area)) continue;
      const double score = acc[x] / (t.norm * std::sqrt(energy));
      if (score > peak.score) {
        peak.score = score;
        peak.at = {a, y};
      }
    }
  }
  return peak;
}

}  // namespace labo::planar
