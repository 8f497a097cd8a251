#include "drone/sim/texture_map.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace labo::sim {

namespace {

TextureMap::Level pack_level(const cv::Mat& bgr, int base_width, int base_height) {
  TextureMap::Level l;
  l.width = bgr.cols;
  l.height = bgr.rows;
  l.stride = bgr.cols + 2;
  l.scale_x = static_cast<float>(bgr.cols) / static_cast<float>(base_width);
  l.scale_y = static_cast<float>(bgr.rows) / static_cast<float>(base_height);
  l.texels.resize(static_cast<std::size_t>(l.stride) * static_cast<std::size_t>(bgr.rows + 2));
  for (int y = -1; y <= bgr.rows; ++y) {
    const auto* row = bgr.ptr<cv::Vec3b>(std::clamp(y, 0, bgr.rows - 1));
    std::uint32_t* out = l.texels.data() + static_cast<std::ptrdiff_t>(y + 1) * l.stride;
    for (int x = -1; x <= bgr.cols; ++x) {
      const cv::Vec3b& c = row[std::clamp(x, 0, bgr.cols - 1)];
      out[x + 1] = pack_bgr(c[0], c[1], c[2]);
    }
  }
  return l;
}

}  // namespace

TextureMap::TextureMap(const cv::Mat& image) {
  if (image.empty()) throw std::invalid_argument("texture: empty image");
  cv::Mat bgr;
  if (image.type() == CV_8UC3) {
    bgr = image;
  } else if (image.type() == CV_8UC1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else {
    throw std::invalid_argument("texture: expected an 8-bit BGR or grey image");
  }
  // Bilinear sampling reads a 2x2 block: pad 1-texel images so every level has two texels a side.
  if (bgr.cols < 2 || bgr.rows < 2) cv::resize(bgr, bgr, cv::Size(std::max(2, bgr.cols), std::max(2, bgr.rows)));
  levels_.push_back(pack_level(bgr, bgr.cols, bgr.rows));
  cv::Mat current = bgr;
  while (current.cols > 4 && current.rows > 4 && levels_.size() < 12) {
    cv::Mat next;
    cv::resize(current, next, cv::Size((current.cols + 1) / 2, (current.rows + 1) / 2), 0, 0, cv::INTER_AREA);
    levels_.push_back(pack_level(next, bgr.cols, bgr.rows));
    current = next;
  }
}

int TextureMap::level_for_footprint(float texels_per_pixel) const {
  if (!(texels_per_pixel > 1.5f)) return 0;
  const int l = static_cast<int>(std::log2(texels_per_pixel / 1.5f)) + 1;
  return std::min(l, level_count() - 1);
}

bool TextureMap::build_area_table() {
  const Level& l = levels_.front();
  const auto w = static_cast<std::size_t>(l.width), h = static_cast<std::size_t>(l.height);
  if (w * h > (std::size_t{1} << 24)) return false;  // 255 * 2^24 < 2^32
  area_.assign((w + 1) * (h + 1) * 3, 0);
  const std::size_t row = (w + 1) * 3;
  for (std::size_t y = 0; y < h; ++y) {
    std::uint32_t b = 0, g = 0, r = 0;  // this row's running sums
    const std::uint32_t* texels = l.origin() + static_cast<std::ptrdiff_t>(y) * l.stride;
    std::uint32_t* above = area_.data() + y * row;
    std::uint32_t* out = above + row;
    for (std::size_t x = 0; x < w; ++x) {
      b += static_cast<std::uint32_t>(texel_b(texels[x]));
      g += static_cast<std::uint32_t>(texel_g(texels[x]));
      r += static_cast<std::uint32_t>(texel_r(texels[x]));
      out[3 * (x + 1)] = above[3 * (x + 1)] + b;
      out[3 * (x + 1) + 1] = above[3 * (x + 1) + 1] + g;
      out[3 * (x + 1) + 2] = above[3 * (x + 1) + 2] + r;
    }
  }
  return true;
}

std::uint32_t TextureMap::box_mean(std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1) const {
  const Level& l = levels_.front();
  const std::int32_t xmax = l.width * 256, ymax = l.height * 256;
  x0 = std::clamp(x0, 0, xmax - 1);
  x1 = std::clamp(x1, x0 + 1, xmax);
  y0 = std::clamp(y0, 0, ymax - 1);
  y1 = std::clamp(y1, y0 + 1, ymax);
  const std::size_t row = static_cast<std::size_t>(l.width + 1) * 3;
  std::int64_t sum[3] = {0, 0, 0};
  // The integral up to (x, y) is bilinear within a texel: the table's four entries around it, weighted
  // in 1/65536; the box is the signed sum of its four corners' integrals.
  const auto corner = [&](std::int32_t x, std::int32_t y, std::int64_t sign) {
    const std::int32_t i = std::min(x >> 8, l.width - 1), j = std::min(y >> 8, l.height - 1);
    const std::int64_t fx = x - (i << 8), fy = y - (j << 8);
    const std::int64_t w00 = (256 - fx) * (256 - fy), w01 = fx * (256 - fy), w10 = (256 - fx) * fy, w11 = fx * fy;
    const std::uint32_t* s0 = area_.data() + static_cast<std::size_t>(j) * row + static_cast<std::size_t>(i) * 3;
    const std::uint32_t* s1 = s0 + row;
    for (int c = 0; c < 3; ++c) sum[c] += sign * (w00 * s0[c] + w01 * s0[c + 3] + w10 * s1[c] + w11 * s1[c + 3]);
  };
  corner(x1, y1, 1);
  corner(x0, y1, -1);
  corner(x1, y0, -1);
  corner(x0, y0, 1);
  // sum / 65536 texel sums over an area of (x1 - x0)(y1 - y0) / 65536 texels.
  const double inverse_area = 1.0 / (static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0));
  int mean[3];
  for (int c = 0; c < 3; ++c) mean[c] = std::clamp(static_cast<int>(static_cast<double>(sum[c]) * inverse_area + 0.5), 0, 255);
  return pack_bgr(mean[0], mean[1], mean[2]);
}

}  // namespace labo::sim
