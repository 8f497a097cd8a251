#include "localization/slam/match/patch_aligner.hpp"

#include <cmath>

namespace labo::slam {
namespace {

// Level-0 pixel centres <-> level pixel centres, with the level's true size ratio (as the extractor).
Eigen::Vector2d ratio(const cv::Mat& level0, const cv::Mat& level) {
  return {static_cast<double>(level0.cols) / level.cols, static_cast<double>(level0.rows) / level.rows};
}
Eigen::Vector2d to_level(const Eigen::Vector2d& px0, const Eigen::Vector2d& r) {
  return {(px0.x() + 0.5) / r.x() - 0.5, (px0.y() + 0.5) / r.y() - 0.5};
}
Eigen::Vector2d to_level0(const Eigen::Vector2d& px, const Eigen::Vector2d& r) {
  return {(px.x() + 0.5) * r.x() - 0.5, (px.y() + 0.5) * r.y() - 0.5};
}

bool inside(const cv::Mat& img, double u, double v) {
  return u >= 0 && v >= 0 && u < img.cols - 1 && v < img.rows - 1;
}

// Bilinear sample of an 8-bit image; the caller checked inside().
float sample(const cv::Mat& img, double u, double v) {
  const int x = static_cast<int>(u), y = static_cast<int>(v);
  const float ax = static_cast<float>(u - x), ay = static_cast<float>(v - y);
  const std::uint8_t* r0 = img.ptr<std::uint8_t>(y) + x;
  const std::uint8_t* r1 = r0 + img.step[0];
  return (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
}

}  // namespace

PatchAligner::PatchAligner(const IdealCamera& camera, const PatchAlignerSettings& settings)
    : camera_(camera), settings_(settings) {}

bool PatchAligner::warp_template(const PatchSource& source, const Eigen::Matrix2d& source_from_frame,
                                 const cv::Mat& source_image) {
  const Eigen::Vector2d centre = to_level(source.image_px, ratio((*source.pyramid)[0], source_image));
  constexpr int r = kSide / 2;
  for (int y = -r; y <= r; ++y) {
    for (int x = -r; x <= r; ++x) {
      const Eigen::Vector2d s = centre + source_from_frame * Eigen::Vector2d(x, y);
      if (!inside(source_image, s.x(), s.y())) return false;
      template_[static_cast<std::size_t>((y + r) * kSide + x + r)] = sample(source_image, s.x(), s.y());
    }
  }
  return true;
}

std::optional<AlignedPosition> PatchAligner::align(const PatchSource& source, const Eigen::Vector3d& p_map,
                                                   const std::vector<cv::Mat>& frame, const Eigen::Isometry3d& T_cam_map,
                                                   const Eigen::Vector2d& start_image_px) {
  if (!source.pyramid || source.pyramid->empty() || frame.empty()) return std::nullopt;
  if (source.level < 0 || source.level >= static_cast<int>(source.pyramid->size())) return std::nullopt;
  const cv::Mat& source_image = (*source.pyramid)[static_cast<std::size_t>(source.level)];
  const Eigen::Vector2d source_ratio = ratio((*source.pyramid)[0], source_image);
  // The affine warp: the source pixel and its two level neighbours, put at the point's depth in the
  // source camera (a patch facing that camera), seen from the frame (real pixels on both sides).
  const double depth = (source.T_cam_map * p_map).z();
  if (depth <= 1e-6) return std::nullopt;
  const Eigen::Isometry3d T_frame_source = T_cam_map * source.T_cam_map.inverse();
  std::array<Eigen::Vector2d, 3> seen;
  const std::array<Eigen::Vector2d, 3> offsets{Eigen::Vector2d(0, 0), Eigen::Vector2d(source_ratio.x(), 0),
                                               Eigen::Vector2d(0, source_ratio.y())};
  for (std::size_t i = 0; i < 3; ++i) {
    const Eigen::Vector2d src = source.image_px + offsets[i];
    const Eigen::Vector2d ideal = camera_.ideal_from_image(src.x(), src.y());
    const Eigen::Vector3d ray((ideal.x() - camera_.cx()) / camera_.fx(), (ideal.y() - camera_.cy()) / camera_.fy(), 1.0);
    const auto px = camera_.real().project(T_frame_source * (ray * depth));
    if (!px) return std::nullopt;
    seen[i] = *px;
  }
  Eigen::Matrix2d A;  // level-0 frame pixels per source level pixel
  A.col(0) = seen[1] - seen[0];
  A.col(1) = seen[2] - seen[0];
  const double det = A.determinant();
  if (!(std::abs(det) > 1e-9)) return std::nullopt;
  // The frame level where the warp is closest to a unit scale (PTAM: det(A) / 4^l closest to 1).
  const double level_scale = static_cast<double>(frame[0].cols) / frame[1 % frame.size()].cols;
  const int levels = static_cast<int>(frame.size());
  int level = static_cast<int>(std::lround(0.5 * std::log(std::abs(det)) / std::log(level_scale)));
  level = std::max(0, std::min(levels - 1, level));
  const cv::Mat& image = frame[static_cast<std::size_t>(level)];
  const Eigen::Vector2d frame_ratio = ratio(frame[0], image);
  Eigen::Matrix2d frame_from_source = A;
  frame_from_source.row(0) /= frame_ratio.x();
  frame_from_source.row(1) /= frame_ratio.y();
  // Refuse strong foreshortening: the patch would be sampled far outside its neighbourhood.
  const Eigen::Matrix2d source_from_frame = frame_from_source.inverse();
  if (source_from_frame.cwiseAbs().rowwise().sum().maxCoeff() > 2.0) return std::nullopt;
  if (!warp_template(source, source_from_frame, source_image)) return std::nullopt;

  // Gradients of the template (central differences) and the Gauss-Newton normal matrix over the
  // window, for (shift x, shift y, brightness offset): inverse-compositional, computed once.
  constexpr int n = 2 * kHalf + 1;
  std::array<float, n * n> gx{}, gy{};
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double mean = 0, mean_sq = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const std::size_t t = static_cast<std::size_t>((y + 1) * kSide + x + 1);
      const std::size_t i = static_cast<std::size_t>(y * n + x);
      gx[i] = 0.5f * (template_[t + 1] - template_[t - 1]);
      gy[i] = 0.5f * (template_[t + kSide] - template_[t - kSide]);
      const Eigen::Vector3d J(gx[i], gy[i], 1.0);
      H += J * J.transpose();
      mean += template_[t];
      mean_sq += static_cast<double>(template_[t]) * template_[t];
    }
  }
  mean /= n * n;
  const double variance = mean_sq / (n * n) - mean * mean;
  if (variance < 4.0) return std::nullopt;  // flat: nothing to align on
  const Eigen::Matrix3d H_inv = H.inverse();
  if (!H_inv.allFinite()) return std::nullopt;

  const Eigen::Vector2d start = to_level(start_image_px, frame_ratio);
  Eigen::Vector2d x = start;
  bool converged = false;
  double residual_sq = 0;
  for (int it = 0; it < settings_.max_iterations; ++it) {
    if (!inside(image, x.x() - kHalf, x.y() - kHalf) || !inside(image, x.x() + kHalf, x.y() + kHalf)) return std::nullopt;
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    residual_sq = 0;
    for (int y = 0; y < n; ++y) {
      for (int u = 0; u < n; ++u) {
        const std::size_t i = static_cast<std::size_t>(y * n + u);
        const double e = sample(image, x.x() + u - kHalf, x.y() + y - kHalf) -
                         template_[static_cast<std::size_t>((y + 1) * kSide + u + 1)];
        b += Eigen::Vector3d(gx[i], gy[i], 1.0) * e;
        residual_sq += e * e;
      }
    }
    const Eigen::Vector3d step = H_inv * b;  // template moved by step.head(2) matches the frame at x
    // What is left after the best shift and brightness offset (linearized): the ratio below.
    residual_sq -= step.dot(b);
    x -= step.head<2>();
    if ((x - start).norm() > settings_.max_shift_px) return std::nullopt;
    if (step.head<2>().norm() < settings_.converged_px) {
      converged = true;
      break;
    }
  }
  if (!converged) return std::nullopt;
  if (std::sqrt(std::max(0.0, residual_sq) / (n * n)) > settings_.max_residual_ratio * std::sqrt(variance)) return std::nullopt;
  return AlignedPosition{to_level0(x, frame_ratio), level};
}

}  // namespace labo::slam
