#include "drone/sim/texture_map.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace labo {

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

std::uint32_t TextureMap::mean_colour() const {
  const Level& l = levels_.back();
  long b = 0, g = 0, r = 0;
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      const std::uint32_t c = l.origin()[y * l.stride + x];
      b += texel_b(c);
      g += texel_g(c);
      r += texel_r(c);
    }
  }
  const long n = static_cast<long>(l.width) * l.height;
  return pack_bgr(static_cast<int>(b / n), static_cast<int>(g / n), static_cast<int>(r / n));
}

}  // namespace labo
