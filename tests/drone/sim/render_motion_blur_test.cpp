// MotionBlur against a camera integrating light over its pixels' area and the shutter time: a step
// edge's profile brute-forced from the moving pixel's coverage, the light moved across the edge, zero
// and sub-threshold motion, and brightness.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/camera_model.hpp"
#include "drone/sim/render_camera_rays.hpp"
#include "drone/sim/render_effects.hpp"

using namespace labo;
using namespace labo::sim;

namespace {

std::uint32_t grey(int v) {
  const auto u = static_cast<std::uint32_t>(v);
  return u | (u << 8) | (u << 16);
}

int blue(std::uint32_t t) { return static_cast<int>(t & 0xFFu); }

struct BlurBench {
  CameraRays rays{PinholeCamera::ardrone2_front()};
  MotionBlur blur{rays};
  int w = rays.width(), h = rays.height();

  void set_all(const Eigen::Vector2f& m) {
    for (int i = 0; i < static_cast<int>(rays.tiles().size()); ++i) blur.set_tile_motion(i, m);
  }
};

// What a pixel at column c sees of a scene that is `dark` left of x = edge - 1/2 and `bright` right of
// it (a scene constant over each pixel cell, as the renderer draws it), its area [c - 1/2, c + 1/2]
// moving by s * mx for s in [-1/2, 1/2] during the exposure: brute force over the shutter time.
double moving_pixel(int c, int edge, double mx, int dark, int bright) {
  constexpr int kSteps = 20000;
  double sum = 0;
  for (int k = 0; k < kSteps; ++k) {
    const double d = ((k + 0.5) / kSteps - 0.5) * mx;
    sum += std::clamp(c - edge + 1 + d, 0.0, 1.0);
  }
  return dark + (bright - dark) * sum / kSteps;
}

}  // namespace

TEST_CASE("motion blur: a step edge blurs as the moving pixel's area integrates it, fractional motions included") {
  BlurBench b;
  constexpr int kDark = 40, kBright = 220, kEdge = 16 * 20 + 7;  // inside a tile
  std::vector<std::uint32_t> src(static_cast<std::size_t>(b.w * b.h)), dst(src.size());
  for (int y = 0; y < b.h; ++y)
    for (int x = 0; x < b.w; ++x) src[static_cast<std::size_t>(y * b.w + x)] = grey(x >= kEdge ? kBright : kDark);
  // The edge is vertical: its profile depends only on the motion across it (x), whatever the motion along it.
  for (const Eigen::Vector2f& m : {Eigen::Vector2f(0.5f, 0.f), Eigen::Vector2f(1.5f, 0.f), Eigen::Vector2f(1.5f, 1.0f),
                                  Eigen::Vector2f(0.3f, 0.f), Eigen::Vector2f(-0.8f, 0.6f), Eigen::Vector2f(4.2f, -2.0f),
                                  Eigen::Vector2f(2.0f, 0.f)}) {
    CAPTURE(m.x(), m.y());
    b.set_all(m);
    b.blur.apply(src.data(), dst.data());
    const int y = b.h / 2 + 3;
    double moved = 0;
    for (int x = kEdge - 6; x <= kEdge + 6; ++x) {
      CAPTURE(x);
      const int out = blue(dst[static_cast<std::size_t>(y * b.w + x)]);
      CHECK(std::abs(out - moving_pixel(x, kEdge, m.x(), kDark, kBright)) <= 1.0);
      moved += std::abs(out - blue(src[static_cast<std::size_t>(y * b.w + x)]));
    }
    // The light carried across the edge: on each side the contrast times the mean of the part of the
    // motion that points into it, |mx| / 8 (whole-pixel taps carried 0 at 0.5 px and 2/3 at 1.5 px).
    // Each pixel is rounded to a grey level: up to 1/2 on each of the (up to 7) pixels that change.
    CHECK(moved == Approx((kBright - kDark) * std::abs(m.x()) / 4).margin(3.0));
  }
}

TEST_CASE("motion blur: zero motion and motion below the threshold leave the image as it is") {
  BlurBench b;
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::uint32_t> texel(0, 0xFFFFFFu);
  std::vector<std::uint32_t> src(static_cast<std::size_t>(b.w * b.h)), dst(src.size());
  for (auto& t : src) t = texel(rng);
  for (const Eigen::Vector2f& m : {Eigen::Vector2f(0.f, 0.f), Eigen::Vector2f(0.01f, -0.008f)}) {
    b.set_all(m);
    std::fill(dst.begin(), dst.end(), 0u);
    b.blur.apply(src.data(), dst.data());
    CHECK(dst == src);
  }
  // One tile just above the threshold: only that tile changes.
  b.set_all(Eigen::Vector2f::Zero());
  const int tile = 5 * b.rays.tiles_x() + 7;
  b.blur.set_tile_motion(tile, Eigen::Vector2f(0.3f, 0.f));
  b.blur.apply(src.data(), dst.data());
  const RenderTile& t = b.rays.tiles()[static_cast<std::size_t>(tile)];
  int changed_inside = 0, changed_outside = 0;
  for (int y = 0; y < b.h; ++y) {
    for (int x = 0; x < b.w; ++x) {
      const bool differs = dst[static_cast<std::size_t>(y * b.w + x)] != src[static_cast<std::size_t>(y * b.w + x)];
      const bool inside = x >= t.x0 && x < t.x1 && y >= t.y0 && y < t.y1;
      (inside ? changed_inside : changed_outside) += differs ? 1 : 0;
    }
  }
  CHECK(changed_outside == 0);
  CHECK(changed_inside > 200);  // random texels: nearly every pixel of the 256 moves by a grey level or more
}

TEST_CASE("motion blur: the kernel's weights sum to one, centred on the pixel, and brightness is conserved") {
  for (const Eigen::Vector2f& m : {Eigen::Vector2f(0.3f, 0.1f), Eigen::Vector2f(1.5f, 0.f), Eigen::Vector2f(2.3f, -1.7f),
                                  Eigen::Vector2f(-7.9f, 3.3f), Eigen::Vector2f(40.f, 25.f)}) {
    CAPTURE(m.x(), m.y());
    MotionBlur::Tap taps[MotionBlur::kMaxTaps];
    const int n = MotionBlur::kernel(m, taps);
    CHECK(n > 1);
    double sum = 0, cx = 0, cy = 0, along = 0;
    const Eigen::Vector2f u = m.normalized();
    for (int k = 0; k < n; ++k) {
      const double wk = taps[k].weight;
      sum += wk;
      cx += wk * taps[k].dx;
      cy += wk * taps[k].dy;
      along += wk * std::pow(u.x() * taps[k].dx + u.y() * taps[k].dy, 2);
    }
    CHECK(sum == 256);
    CHECK(std::abs(cx / 256) < 0.02);
    CHECK(std::abs(cy / 256) < 0.02);
    // The spread along the motion: the box's len^2 / 12 plus at most the bilinear surface's 1/4.
    const double len = std::min(m.norm(), MotionBlur::kMaxMotion_px);
    CHECK(along / 256 >= len * len / 12 - 0.05);
    CHECK(along / 256 <= len * len / 12 + 0.25 + 0.05);
  }

  BlurBench b;
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::uint32_t> texel(0, 0xFFFFFFu);
  std::vector<std::uint32_t> src(static_cast<std::size_t>(b.w * b.h), grey(128)), dst(src.size());
  constexpr int kMargin = 24;  // flat, so the edge's repetition moves no light
  for (int y = kMargin; y < b.h - kMargin; ++y)
    for (int x = kMargin; x < b.w - kMargin; ++x) src[static_cast<std::size_t>(y * b.w + x)] = texel(rng);
  b.set_all(Eigen::Vector2f(2.3f, -1.7f));
  b.blur.apply(src.data(), dst.data());
  CHECK(dst != src);
  for (int shift : {0, 8, 16}) {
    double before = 0, after = 0;
    for (std::size_t i = 0; i < src.size(); ++i) {
      before += (src[i] >> shift) & 0xFFu;
      after += (dst[i] >> shift) & 0xFFu;
    }
    CAPTURE(shift);
    CHECK(std::abs(after - before) / static_cast<double>(src.size()) < 0.02);  // grey levels per pixel
  }
}
