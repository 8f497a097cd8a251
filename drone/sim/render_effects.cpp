#include "drone/sim/render_effects.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "drone/sim/render_vector_clones.hpp"

namespace labo {

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

namespace {

// Averages `taps` texels at the given offsets from each pixel of a row (SWAR: blue and red share a
// word, 16 bits each, green its own: 32 taps of 255 fit). Branch-free, so it vectorizes.
inline void average_taps(const std::uint32_t* const* rows, int taps, int count, std::uint32_t scale, std::uint32_t* out) {
  constexpr int kRow = CameraRays::kTile;
  alignas(32) std::uint32_t rb[kRow], g[kRow];
  for (int i = 0; i < count; ++i) rb[i] = g[i] = 0;
  for (int k = 0; k < taps; ++k) {
    const std::uint32_t* s = rows[k];
    for (int i = 0; i < count; ++i) {
      rb[i] += s[i] & 0x00FF00FFu;
      g[i] += (s[i] >> 8) & 0xFFu;
    }
  }
  for (int i = 0; i < count; ++i) {
    out[i] = (((rb[i] & 0xFFFFu) * scale) >> 16) | ((((g[i] * scale) >> 16)) << 8) | ((((rb[i] >> 16) * scale) >> 16) << 16);
  }
}

}  // namespace

LABO_VECTOR_CLONES void MotionBlur::apply(const std::uint32_t* src, std::uint32_t* dst) const {
  const int w = rays_.width(), h = rays_.height();
  const auto& tiles = rays_.tiles();
  int dx[kMaxTaps], dy[kMaxTaps];
  const std::uint32_t* rows[kMaxTaps];
  std::uint32_t clamped[kMaxTaps][CameraRays::kTile];
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const RenderTile& t = tiles[i];
    const Eigen::Vector2f m = motion_[i];
    const float len = m.norm();
    if (len < 1.f) {
      for (int y = t.y0; y < t.y1; ++y) std::copy(src + y * w + t.x0, src + y * w + t.x1, dst + y * w + t.x0);
      continue;
    }
    const int taps = std::min(kMaxTaps, static_cast<int>(std::ceil(len)) + 1);
    int min_dx = 0, max_dx = 0, min_dy = 0, max_dy = 0;
    for (int k = 0; k < taps; ++k) {
      const float f = static_cast<float>(k) / static_cast<float>(taps - 1) - 0.5f;
      dx[k] = static_cast<int>(std::lround(f * m.x()));
      dy[k] = static_cast<int>(std::lround(f * m.y()));
      min_dx = std::min(min_dx, dx[k]);
      max_dx = std::max(max_dx, dx[k]);
      min_dy = std::min(min_dy, dy[k]);
      max_dy = std::max(max_dy, dy[k]);
    }
    const std::uint32_t scale = 65536u / static_cast<std::uint32_t>(taps);
    const int count = t.x1 - t.x0;
    const bool inside = t.x0 + min_dx >= 0 && t.x1 - 1 + max_dx < w && t.y0 + min_dy >= 0 && t.y1 - 1 + max_dy < h;
    for (int y = t.y0; y < t.y1; ++y) {
      for (int k = 0; k < taps; ++k) {
        if (inside) {
          rows[k] = src + (y + dy[k]) * w + t.x0 + dx[k];
        } else {  // near the border: the taps that fall outside repeat the edge
          const std::uint32_t* row = src + std::clamp(y + dy[k], 0, h - 1) * w;
          for (int j = 0; j < count; ++j) clamped[k][j] = row[std::clamp(t.x0 + j + dx[k], 0, w - 1)];
          rows[k] = clamped[k];
        }
      }
      average_taps(rows, taps, count, scale, dst + y * w + t.x0);
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

}  // namespace labo
