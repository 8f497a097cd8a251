#pragma once
// A mip-mapped texture for the lab renderer: texels packed as 0x00RRGGBB in 32 bits, so a bilinear
// sample is four loads and two multiply-adds per pair of channels (SWAR, no unpacking to floats).
// Level 0 is the image as given; each next level halves it (area average), down to a few texels.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace labo {

// Channel access of a packed texel (B in the low byte).
inline std::uint32_t pack_bgr(int b, int g, int r) {
  return static_cast<std::uint32_t>(b) | (static_cast<std::uint32_t>(g) << 8) | (static_cast<std::uint32_t>(r) << 16);
}
inline int texel_b(std::uint32_t c) { return static_cast<int>(c & 0xFFu); }
inline int texel_g(std::uint32_t c) { return static_cast<int>((c >> 8) & 0xFFu); }
inline int texel_r(std::uint32_t c) { return static_cast<int>((c >> 16) & 0xFFu); }

// The weighted sum of four packed texels, weights in 1/256 summing to 256.
inline std::uint32_t blend4(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, std::uint32_t wa,
                            std::uint32_t wb, std::uint32_t wc, std::uint32_t wd) {
  constexpr std::uint32_t kMask = 0x00FF00FFu;
  const std::uint32_t rb = ((a & kMask) * wa + (b & kMask) * wb + (c & kMask) * wc + (d & kMask) * wd) >> 8;
  const std::uint32_t g = (((a >> 8) & 0xFFu) * wa + ((b >> 8) & 0xFFu) * wb + ((c >> 8) & 0xFFu) * wc +
                           ((d >> 8) & 0xFFu) * wd) >> 8;
  return (rb & kMask) | (g << 8);
}

class TextureMap {
 public:
  struct Level {
    int width = 0, height = 0;
    float scale_x = 1, scale_y = 1;  // level texels per level-0 texel
    std::vector<std::uint32_t> texels;
  };

  TextureMap() = default;
  // `bgr`: CV_8UC3 or CV_8UC1 (grey); throws std::invalid_argument for anything else or an empty image.
  explicit TextureMap(const cv::Mat& bgr);

  int width() const { return levels_.front().width; }
  int height() const { return levels_.front().height; }
  int level_count() const { return static_cast<int>(levels_.size()); }
  const Level& level(int i) const { return levels_[static_cast<std::size_t>(i)]; }

  // The level whose texels are about one pixel wide when one pixel covers `texels_per_pixel` level-0 texels.
  int level_for_footprint(float texels_per_pixel) const;

  // Bilinear sample at level-0 texel coordinates (texel centres at integers), clamped to the edge.
  std::uint32_t sample(int level_index, float u, float v) const {
    const Level& l = levels_[static_cast<std::size_t>(level_index)];
    float x = (u + 0.5f) * l.scale_x - 0.5f, y = (v + 0.5f) * l.scale_y - 0.5f;
    x = x < 0.f ? 0.f : (x > l.width - 1.001f ? l.width - 1.001f : x);
    y = y < 0.f ? 0.f : (y > l.height - 1.001f ? l.height - 1.001f : y);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const auto fx = static_cast<std::uint32_t>((x - static_cast<float>(x0)) * 256.f);
    const auto fy = static_cast<std::uint32_t>((y - static_cast<float>(y0)) * 256.f);
    const std::uint32_t* p = l.texels.data() + static_cast<std::ptrdiff_t>(y0) * l.width + x0;
    const std::uint32_t w11 = (fx * fy) >> 8, w01 = fx - w11, w10 = fy - w11, w00 = 256 - w01 - w10 - w11;
    return blend4(p[0], p[1], p[l.width], p[l.width + 1], w00, w01, w10, w11);
  }

  // The mean colour of level 0 (for untextured stand-ins).
  std::uint32_t mean_colour() const;

 private:
  std::vector<Level> levels_;
};

}  // namespace labo
