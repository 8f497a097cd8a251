#pragma once
// A mip-mapped texture for the lab renderer: texels packed as 0x00RRGGBB in 32 bits, so a bilinear
// sample is four loads and two multiply-adds per pair of channels (SWAR, no unpacking to floats).
// Level 0 is the image as given; each next level halves it (area average), down to a few texels.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace labo::sim {

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
  // Each level has a one-texel border (copies of the edge), so a bilinear sample at level texel
  // coordinates in [-1, width) x [-1, height) never reads outside it.
  struct Level {
    int width = 0, height = 0, stride = 0;  // stride = width + 2
    float scale_x = 1, scale_y = 1;         // level texels per level-0 texel
    std::vector<std::uint32_t> texels;      // (height + 2) rows of `stride`, border included

    const std::uint32_t* origin() const { return texels.data() + stride + 1; }  // texel (0, 0)
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

  // Bilinear sample at level texel coordinates in 16.16 fixed point (texel centres at integers),
  // which must lie in [-1, width) x [-1, height) of that level: no clamping.
  static std::uint32_t sample_fixed(const Level& l, std::int32_t u, std::int32_t v) {
    const std::uint32_t* p = l.origin() + (v >> 16) * l.stride + (u >> 16);
    const auto fx = static_cast<std::uint32_t>(u >> 8) & 0xFFu, fy = static_cast<std::uint32_t>(v >> 8) & 0xFFu;
    const std::uint32_t w11 = (fx * fy) >> 8, w01 = fx - w11, w10 = fy - w11, w00 = 256 - w01 - w10 - w11;
    return blend4(p[0], p[1], p[l.stride], p[l.stride + 1], w00, w01, w10, w11);
  }
  // Level texel coordinate (float) to 16.16 fixed point, clamped to the texel centres' range [-0.5, size - 0.5].
  static std::int32_t to_fixed(float coordinate, int size) {
    const float c = coordinate < -0.5f ? -0.5f : (coordinate > static_cast<float>(size) - 0.5f ? static_cast<float>(size) - 0.5f : coordinate);
    return static_cast<std::int32_t>(c * 65536.f);
  }

  // Bilinear sample at level-0 texel coordinates (texel centres at integers), clamped to the edge.
  std::uint32_t sample(int level_index, float u, float v) const {
    const Level& l = levels_[static_cast<std::size_t>(level_index)];
    return sample_fixed(l, to_fixed((u + 0.5f) * l.scale_x - 0.5f, l.width), to_fixed((v + 0.5f) * l.scale_y - 0.5f, l.height));
  }


  // Area filtering (docs/sim_rendering.md, "Instrument panels: the pixel's area"): a summed-area table
  // of level 0, so that a pixel can record the exact mean of the texels its footprint covers, as a
  // camera's pixel integrates the light falling on it, instead of one bilinear sample of a mip level
  // (whose blur and aliasing depend on the sub-pixel phase and jump with the level). Built on request
  // (the instrument panels and the landing pattern); false for textures larger than 16 M texels (the
  // 32-bit sums would overflow).
  bool build_area_table();
  bool has_area_table() const { return !area_.empty(); }
  // The mean of level 0 over the box [x0, x1) x [y0, y1), in 1/256 level-0 texels with texel edges at
  // multiples of 256 (texel i spans [256 i, 256 (i + 1))), clamped to the texture; x1 > x0, y1 > y0.
  // Exact for the texture's piecewise-constant texels (the table is interpolated bilinearly).
  std::uint32_t box_mean(std::int32_t x0, std::int32_t y0, std::int32_t x1, std::int32_t y1) const;

 private:
  std::vector<Level> levels_;
  // (height + 1) x (width + 1) x 3 (b, g, r): sums of level 0 over [0, x) x [0, y).
  std::vector<std::uint32_t> area_;
};

}  // namespace labo::sim
