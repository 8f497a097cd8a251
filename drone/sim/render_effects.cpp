#include "drone/sim/render_effects.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "drone/sim/render_vector_clones.hpp"

namespace labo::sim {

namespace {

constexpr std::size_t kNoiseTable = std::size_t{1} << 21;  // bytes; a frame uses up to width * height * 3

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// The drone's body pose `dt` after the scene's instant, at constant velocities.
Eigen::Isometry3d body_at(const SceneState& s, double dt) {
  Eigen::Isometry3d T = s.T_world_body;
  T.translation() += s.velocity_world_mps * dt;
  const Eigen::Vector3d w = s.angular_velocity_body_radps * dt;
  if (w.norm() > 1e-12) T.linear() = T.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  return T;
}

}  // namespace

MotionBlur::MotionBlur(const CameraRays& rays) : rays_(rays), motion_(rays.tiles().size(), Eigen::Vector2f::Zero()) {}

float MotionBlur::plan(const SceneState& scene, const Eigen::Isometry3d& T_body_cam, double shutter_s,
                       const std::vector<float>& tile_depth) {
  const Eigen::Isometry3d T_world_cam = scene.T_world_body * T_body_cam;
  const Eigen::Isometry3d T_cam0_world = (body_at(scene, -0.5 * shutter_s) * T_body_cam).inverse();
  const Eigen::Isometry3d T_cam1_world = (body_at(scene, 0.5 * shutter_s) * T_body_cam).inverse();
  const PinholeCamera& camera = rays_.camera();
  float largest = 0;
  const auto& tiles = rays_.tiles();
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    motion_[i].setZero();
    const float z = tile_depth[i];
    if (!(z > 0.f)) continue;
    const auto c = static_cast<std::size_t>(tiles[i].centre);
    const Eigen::Vector3d p_cam(rays_.ray_x()[c] * z, rays_.ray_y()[c] * z, z);
    const Eigen::Vector3d p_world = T_world_cam * p_cam;
    const auto a = camera.project(T_cam0_world * p_world), b = camera.project(T_cam1_world * p_world);
    if (!a || !b) continue;
    motion_[i] = (*b - *a).cast<float>();
    largest = std::max(largest, motion_[i].norm());
  }
  return largest;
}

int MotionBlur::kernel(const Eigen::Vector2f& motion, Tap (&taps)[kMaxTaps]) {
  const float len = motion.norm();
  if (!(len >= kMinMotion_px)) {  // NaN too
    taps[0] = {0, 0, 256};
    return 1;
  }
  const Eigen::Vector2d m = motion.cast<double>() * (len > kMaxMotion_px ? kMaxMotion_px / len : 1.f);
  // The segment p(s) = s * m, s in [-1/2, 1/2], cut where it crosses a cell border (s * m.x or s * m.y an
  // integer): inside each piece the bilinear weights of one cell's 4 corners are linear in s, so their
  // products integrate exactly.
  constexpr int kMaxAxisCuts = static_cast<int>(kMaxMotion_px) + 1;
  double axis_cuts[2][kMaxAxisCuts];  // each axis's in increasing s
  int axis_n[2] = {0, 0};
  for (int axis = 0; axis < 2; ++axis) {
    const double half = 0.5 * std::abs(m[axis]);
    const int first = static_cast<int>(std::floor(-half)) + 1, last = static_cast<int>(std::ceil(half)) - 1;
    for (int k = first; k <= last; ++k) axis_cuts[axis][axis_n[axis]++] = k / std::abs(m[axis]);  // the same set as k / m: (-half, half) is symmetric
  }
  double cuts[2 * kMaxAxisCuts + 2];
  cuts[0] = -0.5;
  const int n = static_cast<int>(std::merge(axis_cuts[0], axis_cuts[0] + axis_n[0], axis_cuts[1], axis_cuts[1] + axis_n[1], cuts + 1) - cuts) + 1;
  cuts[n - 1] = 0.5;

  // The weights on the grid of offsets [-kReach, kReach]^2 (only the segment's box is cleared and read).
  constexpr int kSide = 2 * kReach + 1;
  double grid[kSide][kSide];
  const int x0 = static_cast<int>(std::floor(-0.5 * std::abs(m.x()))), x1 = static_cast<int>(std::floor(0.5 * std::abs(m.x()))) + 1;
  const int y0 = static_cast<int>(std::floor(-0.5 * std::abs(m.y()))), y1 = static_cast<int>(std::floor(0.5 * std::abs(m.y()))) + 1;
  for (int y = y0; y <= y1; ++y) std::fill(grid[y + kReach] + x0 + kReach, grid[y + kReach] + x1 + kReach + 1, 0.0);
  for (int i = 0; i + 1 < n; ++i) {
    const double s0 = cuts[i], s1 = cuts[i + 1], h = s1 - s0;
    if (h <= 0) continue;
    const double mid = 0.5 * (s0 + s1);
    const int a = std::clamp(static_cast<int>(std::floor(mid * m.x())), x0, x1 - 1);
    const int b = std::clamp(static_cast<int>(std::floor(mid * m.y())), y0, y1 - 1);
    // The fractions inside the cell at both ends of the piece; their means and the mean of their product.
    const double fx0 = std::clamp(s0 * m.x() - a, 0.0, 1.0), fx1 = std::clamp(s1 * m.x() - a, 0.0, 1.0);
    const double fy0 = std::clamp(s0 * m.y() - b, 0.0, 1.0), fy1 = std::clamp(s1 * m.y() - b, 0.0, 1.0);
    const double fx = 0.5 * (fx0 + fx1), fy = 0.5 * (fy0 + fy1);
    const double fxy = (fx0 * fy0 + fx1 * fy1) / 3 + (fx0 * fy1 + fx1 * fy0) / 6;
    double* row0 = grid[b + kReach] + a + kReach;
    double* row1 = grid[b + 1 + kReach] + a + kReach;
    row0[0] += h * (1 - fx - fy + fxy);
    row0[1] += h * (fx - fxy);
    row1[0] += h * (fy - fxy);
    row1[1] += h * fxy;
  }

  // To weights in 1/256 summing to 256: the running sum is rounded, so each weight is off by less than
  // 1/256 and none of the rounding piles up on one tap (a 32 px blur has ~100 taps of ~2.5/256).
  int count = 0;
  double sum = 0;
  long rounded = 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      sum += grid[y + kReach][x + kReach];
      const long next = std::lround(256.0 * sum);
      if (next > rounded) taps[count++] = {x, y, static_cast<std::uint32_t>(next - rounded)};
      rounded = std::max(rounded, next);
    }
  }
  if (rounded != 256) taps[count - 1].weight = static_cast<std::uint32_t>(static_cast<long>(taps[count - 1].weight) + 256 - rounded);
  return count;
}

namespace {

// The weighted sum of `taps` texels, one row each, for each pixel of a full tile row. SWAR in 16-bit
// lanes: a texel's blue and red (its bytes 0 and 2) and its green and zero alpha (shifted down a byte)
// each fill two lanes of a word; weights are in 1/256 and sum to 256, so a lane's sum (255 * 256 + 128
// for the rounding) fits its 16 bits and the multiplies are 16-bit ones. Written with GCC's vector
// extensions (8 texels a vector): the loop the compiler would not vectorize this well by itself.
using Texels8 = std::uint32_t __attribute__((vector_size(32)));
using Lanes16 = std::uint16_t __attribute__((vector_size(32)));

inline void weigh_tile_row(const std::uint32_t* const* rows, const std::uint16_t* weights, int taps, std::uint32_t* out) {
  constexpr int kVectors = CameraRays::kTile / 8;
  Lanes16 br[kVectors], ga[kVectors];
  for (int c = 0; c < kVectors; ++c) br[c] = ga[c] = Lanes16{} + 128;
  for (int k = 0; k < taps; ++k) {
    const Lanes16 w = Lanes16{} + weights[k];
    for (int c = 0; c < kVectors; ++c) {
      Texels8 t;
      std::memcpy(&t, rows[k] + 8 * c, sizeof t);
      br[c] += reinterpret_cast<Lanes16>(t & 0x00FF00FFu) * w;
      ga[c] += reinterpret_cast<Lanes16>((t >> 8) & 0x00FF00FFu) * w;
    }
  }
  for (int c = 0; c < kVectors; ++c) {
    const Texels8 t = reinterpret_cast<Texels8>(br[c] >> 8) | (reinterpret_cast<Texels8>(ga[c] >> 8) << 8);
    std::memcpy(out + 8 * c, &t, sizeof t);
  }
}

// The same for a partial row of `count` pixels, one byte at a time.
inline void weigh_row(const std::uint32_t* const* rows, const std::uint16_t* weights, int taps, int count, std::uint32_t* out) {
  for (int i = 0; i < count * 4; ++i) {
    unsigned sum = 128;
    for (int k = 0; k < taps; ++k) sum += reinterpret_cast<const std::uint8_t*>(rows[k])[i] * unsigned{weights[k]};
    reinterpret_cast<std::uint8_t*>(out)[i] = static_cast<std::uint8_t>(sum >> 8);
  }
}

}  // namespace

LABO_VECTOR_CLONES void MotionBlur::apply(const std::uint32_t* src, std::uint32_t* dst) const {
  constexpr int kTile = CameraRays::kTile;
  const int w = rays_.width(), h = rays_.height();
  const auto& tiles = rays_.tiles();
  Tap taps[kMaxTaps];
  std::uint16_t weights[kMaxTaps];
  const std::uint32_t* rows[kMaxTaps];
  // Near the border: the tile's source window with the edge repeated.
  constexpr int kWindow = kTile + 2 * kReach;
  std::uint32_t window[kWindow * kWindow];
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const RenderTile& t = tiles[i];
    const int n = kernel(motion_[i], taps);
    if (n == 1 && taps[0].dx == 0 && taps[0].dy == 0) {
      for (int y = t.y0; y < t.y1; ++y) std::copy(src + y * w + t.x0, src + y * w + t.x1, dst + y * w + t.x0);
      continue;
    }
    int min_dx = 0, max_dx = 0, min_dy = 0, max_dy = 0;
    for (int k = 0; k < n; ++k) {
      weights[k] = static_cast<std::uint16_t>(taps[k].weight);
      min_dx = std::min(min_dx, taps[k].dx);
      max_dx = std::max(max_dx, taps[k].dx);
      min_dy = std::min(min_dy, taps[k].dy);
      max_dy = std::max(max_dy, taps[k].dy);
    }
    const int count = t.x1 - t.x0;
    const bool inside = t.x0 + min_dx >= 0 && t.x1 - 1 + max_dx < w && t.y0 + min_dy >= 0 && t.y1 - 1 + max_dy < h;
    const std::uint32_t* base = src;  // the texel (x, y) at base[(y - oy) * stride + x - ox]
    int stride = w, ox = 0, oy = 0;
    if (!inside) {
      stride = count + max_dx - min_dx;
      ox = t.x0 + min_dx;
      oy = t.y0 + min_dy;
      for (int y = oy; y < t.y1 + max_dy; ++y) {
        const std::uint32_t* row = src + std::clamp(y, 0, h - 1) * w;
        for (int x = ox; x < ox + stride; ++x) window[(y - oy) * stride + x - ox] = row[std::clamp(x, 0, w - 1)];
      }
      base = window;
    }
    for (int y = t.y0; y < t.y1; ++y) {
      for (int k = 0; k < n; ++k) rows[k] = base + (y + taps[k].dy - oy) * stride + t.x0 + taps[k].dx - ox;
      if (count == kTile) {
        weigh_tile_row(rows, weights, n, dst + y * w + t.x0);
      } else {
        weigh_row(rows, weights, n, count, dst + y * w + t.x0);
      }
    }
  }
}

SensorResponse::SensorResponse(unsigned seed, double noise_sigma)
    : seed_hash_(mix(seed)), raise_(kNoiseTable), lower_(kNoiseTable) {
  // Box-Muller on a seeded 64-bit generator: the same table on every platform.
  std::uint64_t state = seed_hash_;
  const auto store = [this](std::size_t i, double value) {
    const long v = std::clamp(std::lround(value), -255L, 255L);
    raise_[i] = static_cast<std::uint8_t>(std::max(0L, v));
    lower_[i] = static_cast<std::uint8_t>(std::max(0L, -v));
  };
  for (std::size_t i = 0; i + 1 < raise_.size(); i += 2) {
    state = mix(state);
    const double u1 = (static_cast<double>(state >> 11) + 1.0) * 0x1.0p-53;
    state = mix(state);
    const double u2 = static_cast<double>(state >> 11) * 0x1.0p-53;
    const double r = noise_sigma * std::sqrt(-2.0 * std::log(u1));
    store(i, r * std::cos(2 * std::numbers::pi * u2));
    store(i + 1, r * std::sin(2 * std::numbers::pi * u2));
  }
}

void SensorResponse::apply(const std::uint32_t* colour, int width, int height, double gain, bool noise, std::uint64_t key,
                           cv::Mat& bgr) const {
  bgr.create(height, width, CV_8UC3);
  // Packed texels are BGRA with A = 0 in memory (little-endian): OpenCV's vectorized conversions apply.
  const cv::Mat packed(height, width, CV_8UC4, const_cast<std::uint32_t*>(colour));
  cv::cvtColor(packed, bgr, cv::COLOR_BGRA2BGR);
  if (std::abs(gain - 1.0) > 1e-6) bgr.convertTo(bgr, CV_8U, gain);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3;
  if (!noise || n > raise_.size()) return;
  // Saturating adds of the positive part, then subtractions of the negative part: the same as
  // clamp(v + noise) since each entry has only one of them.
  const std::size_t offset = mix(seed_hash_ ^ key) % (raise_.size() - n + 1);
  const cv::Mat up(height, width, CV_8UC3, const_cast<std::uint8_t*>(raise_.data() + offset));
  const cv::Mat down(height, width, CV_8UC3, const_cast<std::uint8_t*>(lower_.data() + offset));
  cv::add(bgr, up, bgr);
  cv::subtract(bgr, down, bgr);
}

std::uint64_t frame_key(Seconds t, CameraId camera) {
  return mix(std::bit_cast<std::uint64_t>(t) ^ (static_cast<std::uint64_t>(camera) << 61));
}

}  // namespace labo::sim
