#include "localization/planar/ic_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "localization/planar/planar_template.hpp"

namespace labo {

namespace {

constexpr int kMinLevelSidePx = 16;
constexpr int kGridCells = 8;  // per side, for spreading the samples over the panel

// Level-0 image pixels -> level-j pixels (pixel centres).
cv::Matx33d base_to_level(int level) {
  const double s = std::ldexp(1.0, -level);
  return {s, 0, 0.5 * s - 0.5, 0, s, 0.5 * s - 0.5, 0, 0, 1};
}

cv::Matx33d increment_warp(const Eigen::Matrix<double, 8, 1>& p) {
  return {1 + p[0], p[2], p[4], p[1], 1 + p[3], p[5], p[6], p[7], 1};
}

bool finite(const cv::Matx33d& M) {
  for (double v : M.val) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

// A convex, non-degenerate quadrilateral (a homography of a real plane in front of the camera).
bool plausible_quad(const std::array<cv::Point2d, 4>& c) {
  double sign = 0;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d a = c[(i + 1) % 4] - c[i], b = c[(i + 2) % 4] - c[(i + 1) % 4];
    const double cross = a.x * b.y - a.y * b.x;
    if (std::abs(cross) < 1e-6) return false;
    if (sign == 0) sign = cross;
    if ((cross > 0) != (sign > 0)) return false;
  }
  return true;
}

}  // namespace

struct InverseCompositionalTracker::Sums {
  int total = 0, valid = 0;
  double i = 0, ii = 0, it = 0, t = 0, tt = 0;
  Eigen::Matrix<double, 8, 1> sd_i = Eigen::Matrix<double, 8, 1>::Zero();
  Eigen::Matrix<double, 8, 1> sd = Eigen::Matrix<double, 8, 1>::Zero();
  Eigen::Matrix<double, 8, 8> hessian = Eigen::Matrix<double, 8, 8>::Zero();
};

InverseCompositionalTracker::InverseCompositionalTracker(const cv::Mat& template_gray, const PlanarConfig& config)
    : template_size_(template_gray.size()), config_(config) {
  if (template_gray.empty() || template_gray.type() != CV_8UC1) {
    throw std::invalid_argument("InverseCompositionalTracker: the template must be a non-empty CV_8UC1 image");
  }
  const double cx = (template_gray.cols - 1) / 2.0, cy = (template_gray.rows - 1) / 2.0;
  const double s = std::max(template_gray.cols, template_gray.rows) / 2.0;
  normalized_from_template_ = cv::Matx33d(1 / s, 0, -cx / s, 0, 1 / s, -cy / s, 0, 0, 1);
  cv::Mat level = template_gray;
  for (int k = 0; std::min(level.cols, level.rows) >= kMinLevelSidePx; ++k) {
    build_level(level, k);
    cv::Mat next;
    cv::pyrDown(level, next);
    level = next;
  }
  if (levels_.empty()) throw std::invalid_argument("InverseCompositionalTracker: template too small");
  frame_pyramid_.resize(static_cast<std::size_t>(config_.pyramid_levels));
}

void InverseCompositionalTracker::build_level(const cv::Mat& gray, int k) {
  cv::Mat gx, gy;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  const double pixel = std::ldexp(1.0, k);  // working px per level-k px
  const double s0 = std::max(template_size_.width, template_size_.height) / 2.0;
  const double cx = (template_size_.width - 1) / 2.0, cy = (template_size_.height - 1) / 2.0;

  // The strongest gradients of each grid cell.
  const int cells = std::min(kGridCells, std::max(1, std::min(gray.cols, gray.rows) / 4));
  const int quota = (config_.max_samples + cells * cells - 1) / (cells * cells);
  std::vector<std::pair<float, cv::Point>> chosen, cell;
  for (int cyi = 0; cyi < cells; ++cyi) {
    for (int cxi = 0; cxi < cells; ++cxi) {
      cell.clear();
      const int y0 = std::max(1, cyi * gray.rows / cells), y1 = std::min(gray.rows - 1, (cyi + 1) * gray.rows / cells);
      const int x0 = std::max(1, cxi * gray.cols / cells), x1 = std::min(gray.cols - 1, (cxi + 1) * gray.cols / cells);
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const float m = gx.at<float>(y, x) * gx.at<float>(y, x) + gy.at<float>(y, x) * gy.at<float>(y, x);
          if (m > 1e-6f) cell.emplace_back(m, cv::Point(x, y));
        }
      }
      const auto n = std::min<std::size_t>(cell.size(), static_cast<std::size_t>(quota));
      std::nth_element(cell.begin(), cell.begin() + static_cast<std::ptrdiff_t>(n) - (n > 0 ? 1 : 0), cell.end(),
                       [](const auto& a, const auto& b) { return a.first > b.first; });
      chosen.insert(chosen.end(), cell.begin(), cell.begin() + static_cast<std::ptrdiff_t>(n));
    }
  }
  if (chosen.size() < 32) return;  // nothing to track at this level (and coarser ones are worse)

  Level L;
  double mean = 0, sq = 0;
  for (const auto& c : chosen) mean += gray.at<uchar>(c.second);
  mean /= static_cast<double>(chosen.size());
  for (const auto& c : chosen) sq += std::pow(gray.at<uchar>(c.second) - mean, 2);
  const double rms = std::sqrt(sq / static_cast<double>(chosen.size()));
  if (rms < 1e-3) return;

  std::vector<Eigen::Matrix<double, 8, 1>> rows;
  rows.reserve(chosen.size());
  Eigen::Matrix<double, 8, 1> row_mean = Eigen::Matrix<double, 8, 1>::Zero(), row_t = row_mean;
  double tt = 0;
  for (const auto& c : chosen) {
    const cv::Point p = c.second;
    Sample smp{};
    smp.xn = static_cast<float>(((p.x + 0.5) * pixel - 0.5 - cx) / s0);
    smp.yn = static_cast<float>(((p.y + 0.5) * pixel - 0.5 - cy) / s0);
    smp.t = static_cast<float>((gray.at<uchar>(p) - mean) / rms);
    // Gradient of the normalized template per normalized unit.
    const double gxn = gx.at<float>(p) * s0 / pixel / rms, gyn = gy.at<float>(p) * s0 / pixel / rms;
    const double x = smp.xn, y = smp.yn, radial = gxn * x + gyn * y;
    Eigen::Matrix<double, 8, 1> r;
    r << gxn * x, gyn * x, gxn * y, gyn * y, gxn, gyn, -x * radial, -y * radial;
    rows.push_back(r);
    row_mean += r;
    row_t += r * smp.t;
    tt += smp.t * smp.t;
    L.samples.push_back(smp);
  }
  row_mean /= static_cast<double>(rows.size());
  const Eigen::Matrix<double, 8, 1> gain_coef = row_t / tt;
  L.hessian.setZero();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Eigen::Matrix<double, 8, 1> r = rows[i] - row_mean - gain_coef * L.samples[i].t;
    for (int j = 0; j < 8; ++j) L.samples[i].sd[static_cast<std::size_t>(j)] = static_cast<float>(r[j]);
    L.hessian += r * r.transpose();
  }
  Eigen::FullPivLU<Eigen::Matrix<double, 8, 8>> lu(L.hessian);
  if (!lu.isInvertible()) return;
  L.hessian_inverse = lu.inverse();
  if (static_cast<int>(levels_.size()) == k) levels_.push_back(std::move(L));
}

InverseCompositionalTracker::Sums InverseCompositionalTracker::accumulate(const Level& level, const cv::Mat& image,
                                                                          const cv::Matx33d& P,
                                                                          bool need_hessian) const {
  Sums s;
  s.total = static_cast<int>(level.samples.size());
  const double xmax = image.cols - 1, ymax = image.rows - 1;
  const std::size_t step = image.step;
  for (const Sample& smp : level.samples) {
    const double w = P(2, 0) * smp.xn + P(2, 1) * smp.yn + P(2, 2);
    const double x = (P(0, 0) * smp.xn + P(0, 1) * smp.yn + P(0, 2)) / w;
    const double y = (P(1, 0) * smp.xn + P(1, 1) * smp.yn + P(1, 2)) / w;
    if (!(x >= 0 && y >= 0 && x < xmax && y < ymax)) continue;  // also false for NaN
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const double fx = x - x0, fy = y - y0;
    const uchar* r0 = image.ptr<uchar>(y0) + x0;
    const uchar* r1 = r0 + step;
    const double top = r0[0] + fx * (r0[1] - r0[0]);
    const double bottom = r1[0] + fx * (r1[1] - r1[0]);
    const double v = top + fy * (bottom - top);
    ++s.valid;
    s.i += v;
    s.ii += v * v;
    s.it += v * smp.t;
    s.t += smp.t;
    s.tt += static_cast<double>(smp.t) * smp.t;
    for (int j = 0; j < 8; ++j) {
      s.sd_i[j] += smp.sd[static_cast<std::size_t>(j)] * v;
      s.sd[j] += smp.sd[static_cast<std::size_t>(j)];
    }
    if (need_hessian) {
      const Eigen::Map<const Eigen::Matrix<float, 8, 1>> r(smp.sd.data());
      s.hessian += (r * r.transpose()).cast<double>();
    }
  }
  return s;
}

TrackOutcome InverseCompositionalTracker::track(const cv::Mat& image, const cv::Matx33d& H_prior) {
  TrackOutcome out;
  out.H = H_prior;
  if (image.empty() || image.type() != CV_8UC1) {
    out.failure = "frame is not a non-empty CV_8UC1 image";
    return out;
  }
  cv::Matx33d M = H_prior * normalized_from_template_.inv();  // normalized -> level-0 image px
  if (!finite(M)) {
    out.failure = "degenerate prior";
    return out;
  }
  const int base = matching_template_level(H_prior, template_size_, static_cast<int>(levels_.size()) - 1);
  const int n_levels = std::min(config_.pyramid_levels, static_cast<int>(levels_.size()) - base);
  for (int j = 1; j < n_levels; ++j) {
    const cv::Mat& previous = j == 1 ? image : frame_pyramid_[static_cast<std::size_t>(j - 1)];
    cv::pyrDown(previous, frame_pyramid_[static_cast<std::size_t>(j)]);  // reuses the buffer
  }
  const std::array<cv::Point2d, 4> corners_n{cv::Point2d(-1, -1), cv::Point2d(1, -1), cv::Point2d(1, 1),
                                             cv::Point2d(-1, 1)};
  double last_step = 1e9;
  for (int j = n_levels - 1; j >= 0; --j) {
    const Level& level = levels_[static_cast<std::size_t>(base + j)];
    const cv::Mat& img = j == 0 ? image : frame_pyramid_[static_cast<std::size_t>(j)];
    const cv::Matx33d S = base_to_level(j);
    const double tolerance = config_.convergence_px * std::ldexp(1.0, j);
    bool partial = false;
    for (int it = 0; it < config_.max_iterations; ++it) {
      Sums s = accumulate(level, img, S * M, partial);
      ++out.iterations;
      if (s.valid < std::max(32, s.total / 4)) {
        out.failure = "object out of view";
        return out;
      }
      const double n = s.valid, mean_i = s.i / n, mean_t = s.t / n;
      const double gain = (s.it - n * mean_i * mean_t) / (s.tt - n * mean_t * mean_t);
      if (!(gain > 1e-3)) {
        out.failure = "no correlation with the template";
        return out;
      }
      if (s.valid < s.total && !partial) {
        partial = true;  // recompute with the Hessian of the visible samples
        s = accumulate(level, img, S * M, true);
      }
      const Eigen::Matrix<double, 8, 1> b = (s.sd_i - mean_i * s.sd) / gain;
      const Eigen::Matrix<double, 8, 1> dp =
          partial ? Eigen::Matrix<double, 8, 1>(s.hessian.ldlt().solve(b)) : Eigen::Matrix<double, 8, 1>(level.hessian_inverse * b);
      const cv::Matx33d M_new = M * increment_warp(dp).inv();
      if (!finite(M_new) || !dp.allFinite()) {
        out.failure = "diverged";
        return out;
      }
      last_step = 0;
      for (const auto& c : corners_n) {
        last_step = std::max(last_step, cv::norm(apply_homography(M_new, c) - apply_homography(M, c)));
      }
      M = M_new;
      if (last_step < tolerance) break;
    }
  }
  out.H = M * normalized_from_template_;
  out.H *= 1.0 / out.H(2, 2);
  if (!finite(out.H) || !plausible_quad(map_corners(out.H, {cv::Point2d(0, 0), cv::Point2d(template_size_.width, 0),
                                                           cv::Point2d(template_size_.width, template_size_.height),
                                                           cv::Point2d(0, template_size_.height)}))) {
    out.failure = "degenerate homography";
    return out;
  }
  // Correlation of the aligned samples at the finest level used.
  const Sums s = accumulate(levels_[static_cast<std::size_t>(base)], image, M, false);
  const double n = std::max(1, s.valid), mi = s.i / n, mt = s.t / n;
  const double denom = std::sqrt(std::max(0.0, (s.ii - n * mi * mi) * (s.tt - n * mt * mt)));
  out.correlation = denom > 0 ? (s.it - n * mi * mt) / denom : 0.0;
  if (last_step > 0.1) {
    out.failure = "no convergence within the iteration limit";
    return out;
  }
  out.converged = true;
  return out;
}

}  // namespace labo
