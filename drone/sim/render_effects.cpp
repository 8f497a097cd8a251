#include "drone/sim/render_effects.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

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

void MotionBlur::apply(const std::uint32_t* src, std::uint32_t* dst) const {
  const int w = rays_.width(), h = rays_.height();
  const auto& tiles = rays_.tiles();
  int dx[kMaxTaps], dy[kMaxTaps];
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const RenderTile& t = tiles[i];
    const Eigen::Vector2f m = motion_[i];
    const float len = m.norm();
    if (len < 1.f) {
      for (int y = t.y0; y < t.y1; ++y) std::copy(src + y * w + t.x0, src + y * w + t.x1, dst + y * w + t.x0);
      continue;
    }
    const int taps = std::min(kMaxTaps, static_cast<int>(std::ceil(len)) + 1);
    for (int k = 0; k < taps; ++k) {
      const float f = static_cast<float>(k) / static_cast<float>(taps - 1) - 0.5f;
      dx[k] = static_cast<int>(std::lround(f * m.x()));
      dy[k] = static_cast<int>(std::lround(f * m.y()));
    }
    const std::uint32_t scale = 65536u / static_cast<std::uint32_t>(taps);
    for (int y = t.y0; y < t.y1; ++y) {
      for (int x = t.x0; x < t.x1; ++x) {
        std::uint32_t rb = 0, g = 0;
        for (int k = 0; k < taps; ++k) {
          const int sx = std::clamp(x + dx[k], 0, w - 1), sy = std::clamp(y + dy[k], 0, h - 1);
          const std::uint32_t c = src[sy * w + sx];
          rb += c & 0x00FF00FFu;  // 16-bit lanes: 32 taps of 255 fit
          g += (c >> 8) & 0xFFu;
        }
        const std::uint32_t b = ((rb & 0xFFFFu) * scale) >> 16, r = ((rb >> 16) * scale) >> 16, gg = (g * scale) >> 16;
        dst[y * w + x] = b | (gg << 8) | (r << 16);
      }
    }
  }
}

SensorResponse::SensorResponse(unsigned seed, double noise_sigma) : seed_hash_(mix(seed)), noise_(kNoiseTable) {
  // Box-Muller on a seeded 64-bit generator: the same table on every platform.
  std::uint64_t state = seed_hash_;
  for (std::size_t i = 0; i < noise_.size(); i += 2) {
    state = mix(state);
    const double u1 = (static_cast<double>(state >> 11) + 1.0) * 0x1.0p-53;
    state = mix(state);
    const double u2 = static_cast<double>(state >> 11) * 0x1.0p-53;
    const double r = noise_sigma * std::sqrt(-2.0 * std::log(u1));
    noise_[i] = static_cast<std::int8_t>(std::clamp(std::lround(r * std::cos(2 * std::numbers::pi * u2)), -127L, 127L));
    if (i + 1 < noise_.size()) noise_[i + 1] = static_cast<std::int8_t>(std::clamp(std::lround(r * std::sin(2 * std::numbers::pi * u2)), -127L, 127L));
  }
}

void SensorResponse::apply(const std::uint32_t* colour, int width, int height, double gain, bool noise, std::uint64_t key,
                           cv::Mat& bgr) const {
  bgr.create(height, width, CV_8UC3);
  std::uint8_t lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = static_cast<std::uint8_t>(std::clamp(std::lround(i * gain), 0L, 255L));
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool with_noise = noise && n * 3 <= noise_.size();
  const std::int8_t* nz = noise_.data() + (with_noise ? mix(seed_hash_ ^ key) % (noise_.size() - n * 3 + 1) : 0);
  for (int y = 0; y < height; ++y) {
    std::uint8_t* out = bgr.ptr<std::uint8_t>(y);
    const std::uint32_t* in = colour + static_cast<std::ptrdiff_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      const std::uint32_t c = in[x];
      out[3 * x + 0] = lut[c & 0xFFu];
      out[3 * x + 1] = lut[(c >> 8) & 0xFFu];
      out[3 * x + 2] = lut[(c >> 16) & 0xFFu];
    }
    if (with_noise) {
      const std::int8_t* row_noise = nz + static_cast<std::ptrdiff_t>(y) * width * 3;
      for (int i = 0; i < width * 3; ++i) out[i] = static_cast<std::uint8_t>(std::clamp(out[i] + row_noise[i], 0, 255));
    }
  }
}

std::uint64_t frame_key(Seconds t, CameraId camera) {
  return mix(std::bit_cast<std::uint64_t>(t) ^ (static_cast<std::uint64_t>(camera) << 61));
}

}  // namespace labo
