#include "localization/planar/track/ic_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "localization/planar/image_ops.hpp"

#include "localization/planar/bilinear_sample.hpp"
#include "localization/planar/planar_template.hpp"

namespace labo::planar {

namespace {

constexpr int kMinLevelSidePx = 16;
constexpr int kGridCells = 8;  // per side, for spreading the samples over the panel
// The frame must show at least a quarter of the samples, or (a panel larger than the view: the landing
// platform below ~0.7 m, a sixth of it in view at 0.3 m) this many; never fewer than kMinSamples.
constexpr int kMinSamples = 32;
constexpr int kEnoughSamples = 100;
// IC's Hessian comes from the template level's gradients; when the frame is sharper than that level
// (the level rule allows a template up to 0.3 octave coarser than the panel's image) the true
// curvature is larger along some direction and the full Gauss-Newton step jumps across the minimum.
// In the simulated lab's approach the oscilloscope at 2.3-2.4 m (panel ~97 px, level 80 px) fell
// into a period-2 cycle (corners moving 0.2-0.3 px back and forth for 30 iterations, correlation
// alternating 0.9974 / 0.9972) and was lost for no convergence. A step that undoes the previous one
// (corner moves pointing back, cosine below -kReversal) is halved: the minimum lies half way.
constexpr double kReversal = 0.5;

bool reverses(const std::array<cv::Point2d, 4>& move, const std::array<cv::Point2d, 4>& previous) {
  double dot = 0, a = 0, b = 0;
  for (std::size_t c = 0; c < 4; ++c) {
    dot += move[c].dot(previous[c]);
    a += move[c].dot(move[c]);
    b += previous[c].dot(previous[c]);
  }
  return dot < -kReversal * std::sqrt(a * b);
}

// Level-0 image pixels -> level-j pixels. cv::pyrDown keeps every other pixel (level-1 pixel i is
// centred on level-0 pixel 2i), so this is a pure scale (not the area-resize convention).
cv::Matx33d base_to_level(int level) {
  const double s = std::ldexp(1.0, -level);
  return {s, 0, 0, 0, s, 0, 0, 0, 1};
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

// Bilinear sample of an 8-bit image at the homography image of (xn, yn); false outside.
inline bool sample_at(const cv::Mat& image, const cv::Matx33d& P, double xn, double yn, double& value) {
  const double w = P(2, 0) * xn + P(2, 1) * yn + P(2, 2);
  const double x = (P(0, 0) * xn + P(0, 1) * yn + P(0, 2)) / w;
  const double y = (P(1, 0) * xn + P(1, 1) * yn + P(1, 2)) / w;
  if (!(x >= 0 && y >= 0 && x < image.cols - 1 && y < image.rows - 1)) return false;
  value = bilinear_grey(image, x, y);
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

namespace {
double correlation_of(int valid, double si, double sii, double st, double stt, double sit) {
  const double n = std::max(1, valid), mi = si / n, mt = st / n;
  const double denom = std::sqrt(std::max(0.0, (sii - n * mi * mi) * (stt - n * mt * mt)));
  return denom > 0 ? (sit - n * mi * mt) / denom : 0.0;
}
}  // namespace

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
    if (config_.ic_smoothing_sigma > 0) {
      cv::Mat smooth;
      cv::GaussianBlur(level, smooth, cv::Size(0, 0), config_.ic_smoothing_sigma);
      build_level(smooth, k);
    } else {
      build_level(level, k);
    }
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
    smp.xn = static_cast<float>((p.x * pixel - cx) / s0);  // pyrDown geometry, see base_to_level
    smp.yn = static_cast<float>((p.y * pixel - cy) / s0);
    smp.t = static_cast<float>((gray.at<uchar>(p) - mean) / rms);
    // Gradient of the normalized template per normalized unit.
    const double gxn = gx.at<float>(p) * s0 / pixel / rms, gyn = gy.at<float>(p) * s0 / pixel / rms;
    smp.gx = static_cast<float>(gxn);
    smp.gy = static_cast<float>(gyn);
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
  const int stride = std::max(1, static_cast<int>(std::sqrt(gray.rows * gray.cols / double(config_.max_samples))));
  for (int y = 1; y + 1 < gray.rows; y += stride) {
    for (int x = 1; x + 1 < gray.cols; x += stride) {
      Sample g{};
      g.xn = static_cast<float>((x * pixel - cx) / s0);
      g.yn = static_cast<float>((y * pixel - cy) / s0);
      g.t = static_cast<float>(gray.at<uchar>(y, x));
      L.grid.push_back(g);
    }
  }
  Eigen::FullPivLU<Eigen::Matrix<double, 8, 8>> lu(L.hessian);
  if (!lu.isInvertible()) return;
  L.hessian_inverse = lu.inverse();
  if (static_cast<int>(levels_.size()) == k) levels_.push_back(std::move(L));
}

InverseCompositionalTracker::Sums InverseCompositionalTracker::accumulate(const std::vector<Sample>& samples,
                                                                          const cv::Mat& image, const cv::Matx33d& P,
                                                                          bool need_hessian) const {
  Sums s;
  s.total = static_cast<int>(samples.size());
  for (const Sample& smp : samples) {
    double v = 0;
    if (!sample_at(image, P, smp.xn, smp.yn, v)) continue;  // outside (or NaN)
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

InverseCompositionalTracker::EsmStep InverseCompositionalTracker::esm_step(const std::vector<Sample>& samples,
                                                                           const cv::Mat& image, const cv::Matx33d& M,
                                                                           double gain, double h) const {
  // Least squares on e = (i - bias) / gain - t with the Jacobian 0.5 (grad t + grad i / gain) dW/dp;
  // bias and gain are re-estimated from this pass's sums, the Jacobian uses the previous gain.
  EsmStep out;
  Eigen::Matrix<double, 8, 8> JtJ = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 8, 1> Jt_i = Eigen::Matrix<double, 8, 1>::Zero(), Jt_t = Jt_i, Jt_1 = Jt_i;
  double n = 0, si = 0, st = 0, sit = 0, stt = 0;
  for (const Sample& smp : samples) {
    double v = 0, xp = 0, xm = 0, yp = 0, ym = 0;
    if (!sample_at(image, M, smp.xn, smp.yn, v) || !sample_at(image, M, smp.xn + h, smp.yn, xp) ||
        !sample_at(image, M, smp.xn - h, smp.yn, xm) || !sample_at(image, M, smp.xn, smp.yn + h, yp) ||
        !sample_at(image, M, smp.xn, smp.yn - h, ym)) {
      continue;
    }
    const double gx = 0.5 * (smp.gx + (xp - xm) / (2 * h) / gain);
    const double gy = 0.5 * (smp.gy + (yp - ym) / (2 * h) / gain);
    const double x = smp.xn, y = smp.yn, radial = gx * x + gy * y;
    Eigen::Matrix<double, 8, 1> r;
    r << gx * x, gy * x, gx * y, gy * y, gx, gy, -x * radial, -y * radial;
    JtJ.selfadjointView<Eigen::Lower>().rankUpdate(r);
    Jt_i += r * v;
    Jt_t += r * smp.t;
    Jt_1 += r;
    n += 1;
    si += v;
    st += smp.t;
    sit += v * smp.t;
    stt += static_cast<double>(smp.t) * smp.t;
  }
  if (n < 32) return out;
  out.gain = (sit - si * st / n) / (stt - st * st / n);
  if (!(out.gain > 1e-3)) return out;
  const double bias = (si - out.gain * st) / n;
  const Eigen::Matrix<double, 8, 1> Jt_e = (Jt_i - bias * Jt_1) / out.gain - Jt_t;
  out.dp = -JtJ.selfadjointView<Eigen::Lower>().ldlt().solve(Jt_e);
  out.ok = out.dp.allFinite();
  return out;
}

void InverseCompositionalTracker::polish_with_esm(const Level& level, const cv::Mat& image, int base, cv::Matx33d& M,
                                                  int& iterations) const {
  // ESM polish (see the header: removes IC's bias when the frame is blurred). Kept only when it
  // raises the correlation on the level's samples; IC's result stands otherwise.
  const double h = std::ldexp(1.0, base) / (std::max(template_size_.width, template_size_.height) / 2.0);
  const Sums before = accumulate(level.samples, image, M, false);
  if (before.valid == 0) return;
  const double rho_before = correlation_of(before.valid, before.i, before.ii, before.t, before.tt, before.it);
  double gain = std::max(1e-3, (before.it - before.i * before.t / before.valid) /
                                   (before.tt - before.t * before.t / before.valid));
  cv::Matx33d polished = M;
  for (int it = 0; it < config_.esm_iterations; ++it) {
    const EsmStep step = esm_step(level.samples, image, polished, gain, h);
    ++iterations;
    if (!step.ok) break;
    gain = step.gain;
    const cv::Matx33d next = polished * increment_warp(step.dp);
    if (!finite(next)) break;
    const std::array<cv::Point2d, 4> corners{cv::Point2d(-1, -1), cv::Point2d(1, -1), cv::Point2d(1, 1), cv::Point2d(-1, 1)};
    double moved = 0;
    for (const auto& c : corners) moved = std::max(moved, cv::norm(apply_homography(next, c) - apply_homography(polished, c)));
    polished = next;
    if (moved < config_.convergence_px) break;
  }
  const Sums after = accumulate(level.samples, image, polished, false);
  if (correlation_of(after.valid, after.i, after.ii, after.t, after.tt, after.it) > rho_before) M = polished;
}

HomographyTrackOutcome InverseCompositionalTracker::track(const cv::Mat& image, const cv::Matx33d& H_prior) {
  HomographyTrackOutcome out;
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
    // Not cv::pyrDown, which allocates row buffers on every call: the same pixels, reused buffers.
    pyr_down_8u(previous, frame_pyramid_[static_cast<std::size_t>(j)], pyramid_scratch_);
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
    // Guard against drift: keep the warp of the best correlation seen on this level's samples and
    // stop once it has not improved for a few iterations (IC's fixed point can slide along weakly
    // constrained directions when the frame is much blurrier than the template).
    double best_rho = -2;
    cv::Matx33d best_M = M;
    int since_best = 0;
    // The corners' move of the previous step (see kReversal).
    std::array<cv::Point2d, 4> previous_move{};
    for (int it = 0; it < config_.max_iterations; ++it) {
      Sums s = accumulate(level.samples, img, S * M, partial);
      ++out.iterations;
      const double rho = correlation_of(s.valid, s.i, s.ii, s.t, s.tt, s.it);
      if (rho >= best_rho) {
        best_rho = rho;
        best_M = M;
        since_best = 0;
      } else if (rho < best_rho - 2e-3 && ++since_best >= 2) {
        M = best_M;
        last_step = 0;
        break;
      }
      if (s.valid < kMinSamples || (s.valid < s.total / 4 && s.valid < kEnoughSamples)) {
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
        s = accumulate(level.samples, img, S * M, true);
      }
      const Eigen::Matrix<double, 8, 1> b = (s.sd_i - mean_i * s.sd) / gain;
      const Eigen::Matrix<double, 8, 1> dp =
          partial ? Eigen::Matrix<double, 8, 1>(s.hessian.ldlt().solve(b)) : Eigen::Matrix<double, 8, 1>(level.hessian_inverse * b);
      cv::Matx33d M_new = M * increment_warp(dp).inv();
      if (!finite(M_new) || !dp.allFinite()) {
        out.failure = "diverged";
        return out;
      }
      std::array<cv::Point2d, 4> move;
      for (std::size_t c = 0; c < 4; ++c) move[c] = apply_homography(M_new, corners_n[c]) - apply_homography(M, corners_n[c]);
      if (reverses(move, previous_move)) {  // an overshoot cycle: the minimum is half way
        M_new = M * increment_warp(0.5 * dp).inv();
        for (auto& m : move) m *= 0.5;
      }
      last_step = 0;
      for (const auto& m : move) last_step = std::max(last_step, cv::norm(m));
      previous_move = move;
      M = M_new;
      if (last_step < tolerance) break;
    }
    if (j == 0 && config_.esm_iterations > 0) polish_with_esm(level, image, base, M, out.iterations);
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
  const Sums s = accumulate(levels_[static_cast<std::size_t>(base)].grid, image, M, false);
  out.correlation = correlation_of(s.valid, s.i, s.ii, s.t, s.tt, s.it);
  if (last_step > 0.1) {
    out.failure = "no convergence within the iteration limit";
    return out;
  }
  out.converged = true;
  return out;
}

}  // namespace labo::planar
