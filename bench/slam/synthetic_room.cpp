#include "bench/slam/synthetic_room.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace labo::bench {

namespace {

cv::Mat procedural_texture(int width, int height, cv::RNG& rng, double density) {
  cv::Mat t(height, width, CV_8U, cv::Scalar(rng.uniform(90, 170)));
  const int shapes = static_cast<int>(density * width * height / 4000.0);
  for (int i = 0; i < shapes; ++i) {
    const int kind = rng.uniform(0, 4);
    const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
    const int size = static_cast<int>(std::exp(rng.uniform(std::log(4.0), std::log(std::max(8.0, width / 8.0)))));
    const cv::Scalar grey(rng.uniform(0, 256));
    if (kind == 0) {
      cv::rectangle(t, c, c + cv::Point(size, size * rng.uniform(1, 4) / 2), grey, cv::FILLED);
    } else if (kind == 1) {
      cv::circle(t, c, size / 2 + 1, grey, cv::FILLED);
    } else if (kind == 2) {
      cv::line(t, c, c + cv::Point(rng.uniform(-size, size), rng.uniform(-size, size)), grey, std::max(1, size / 10));
    } else {
      std::string text;
      for (int k = 0; k < 3; ++k) text += static_cast<char>('A' + rng.uniform(0, 26));
      cv::putText(t, text, c, cv::FONT_HERSHEY_SIMPLEX, std::max(0.3, size / 25.0), grey, std::max(1, size / 12));
    }
  }
  cv::GaussianBlur(t, t, cv::Size(3, 3), 0.8);
  return t;
}

}  // namespace

SyntheticRoom::SyntheticRoom(const PinholeCamera& camera, const SyntheticRoomSpec& spec) : camera_(camera), spec_(spec) {
  cv::RNG rng(spec.seed);
  const Eigen::Vector3d size = spec.max_corner - spec.min_corner;
  auto make = [&](double u_m, double v_m, double texel, double density) {
    Texture tex;
    tex.texel_m = texel;
    cv::Mat base = procedural_texture(static_cast<int>(u_m / texel), static_cast<int>(v_m / texel), rng, density);
    cv::Mat f;
    base.convertTo(f, CV_32F);
    tex.mips.push_back(f);
    while (tex.mips.back().cols > 16 && tex.mips.back().rows > 16) {
      cv::Mat down;
      cv::pyrDown(tex.mips.back(), down);
      tex.mips.push_back(down);
    }
    return tex;
  };
  faces_[0] = make(size.y(), size.z(), spec.texel_m, 1.0);
  faces_[1] = make(size.y(), size.z(), spec.texel_m, 1.0);
  faces_[2] = make(size.x(), size.z(), spec.texel_m, 1.0);
  faces_[3] = make(size.x(), size.z(), spec.texel_m, 1.0);
  faces_[4] = make(size.x(), size.y(), spec.texel_m, 0.5);
  faces_[5] = make(size.x(), size.y(), spec.texel_m, 0.3);
  panel_ = make(spec.panel_size.x(), spec.panel_size.y(), spec.panel_texel_m, 0.6);
  rays_.resize(static_cast<std::size_t>(camera.width() * camera.height()));
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) {
      rays_[static_cast<std::size_t>(v * camera.width() + u)] = camera.unproject({u, v}).cast<float>();
    }
  }
}

Eigen::Vector3d SyntheticRoom::panel_center() const {
  return {spec_.max_corner.x(), spec_.panel_center_yz.x(), spec_.panel_center_yz.y()};
}

float SyntheticRoom::sample(const Texture& t, double u_m, double v_m, double footprint_m) const {
  const double ratio = footprint_m / t.texel_m;
  int level = 0;
  for (double r = ratio; r > 1.5 && level + 1 < static_cast<int>(t.mips.size()); r *= 0.5) ++level;
  const cv::Mat& m = t.mips[static_cast<std::size_t>(level)];
  const double scale = static_cast<double>(m.cols) / t.mips[0].cols;
  const double x = std::clamp(u_m / t.texel_m * scale - 0.5, 0.0, m.cols - 1.001);
  const double y = std::clamp(v_m / t.texel_m * scale - 0.5, 0.0, m.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
  const float a = static_cast<float>(x - x0), b = static_cast<float>(y - y0);
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y1);
  return (1 - a) * (1 - b) * r0[x0] + a * (1 - b) * r0[x1] + (1 - a) * b * r1[x0] + a * b * r1[x1];
}

cv::Mat SyntheticRoom::render(const Eigen::Isometry3d& T_world_cam, unsigned frame_seed) const {
  const int w = camera_.width(), h = camera_.height();
  cv::Mat out(h, w, CV_8U);
  const Eigen::Matrix3f R = T_world_cam.linear().cast<float>();
  const Eigen::Vector3d o = T_world_cam.translation();
  const Eigen::Vector3d lo = spec_.min_corner, hi = spec_.max_corner;
  const double pixel_angle = 1.0 / camera_.intrinsics().fx;
  cv::Mat noise(h, w, CV_32F);
  cv::RNG rng(spec_.seed * 7919u + frame_seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, spec_.noise_sigma);
  for (int v = 0; v < h; ++v) {
    auto* row = out.ptr<std::uint8_t>(v);
    const float* nrow = noise.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d d = (R * rays_[static_cast<std::size_t>(v * w + u)]).cast<double>();
      double best = 1e18;
      int axis = 0;
      for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) continue;
        const double t = ((d[a] > 0 ? hi[a] : lo[a]) - o[a]) / d[a];
        if (t < best) {
          best = t;
          axis = a;
        }
      }
      const Eigen::Vector3d p = o + best * d;
      const int face = axis * 2 + (d[axis] > 0 ? 1 : 0);
      const double footprint = best * pixel_angle / std::max(0.05, std::abs(d[axis]));
      float grey;
      if (face == 1 && std::abs(p.y() - spec_.panel_center_yz.x()) < spec_.panel_size.x() / 2 &&
          std::abs(p.z() - spec_.panel_center_yz.y()) < spec_.panel_size.y() / 2) {
        // Panel seen from inside the room: its x to the viewer's right is -y, its y down is -z.
        grey = sample(panel_, spec_.panel_size.x() / 2 - (p.y() - spec_.panel_center_yz.x()),
                      spec_.panel_size.y() / 2 - (p.z() - spec_.panel_center_yz.y()), footprint);
      } else if (axis == 0) {
        grey = sample(faces_[static_cast<std::size_t>(face)], p.y() - lo.y(), hi.z() - p.z(), footprint);
      } else if (axis == 1) {
        grey = sample(faces_[static_cast<std::size_t>(face)], p.x() - lo.x(), hi.z() - p.z(), footprint);
      } else {
        grey = sample(faces_[static_cast<std::size_t>(face)], p.x() - lo.x(), p.y() - lo.y(), footprint);
      }
      row[u] = cv::saturate_cast<std::uint8_t>(grey + nrow[u]);
    }
  }
  return out;
}

}  // namespace labo::bench
