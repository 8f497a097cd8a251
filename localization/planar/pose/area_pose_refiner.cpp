#include "localization/planar/pose/area_pose_refiner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "localization/planar/pose/photometric_gauss_newton.hpp"

namespace labo::planar {

namespace {

constexpr int kBlurParam = kPhotometricBlurParam;
constexpr int kMinPixels = 50;
constexpr int kCells = 6;  // per side, as Se3PoseRefiner: the pixels are spread over the panel
// A pixel is fitted when its widened footprint, grown by this many frame px, lies on the panel: the
// lens's blur reaches that far, and beyond the panel's edge the frame shows the housing, which the
// template does not know.
constexpr double kEdgeMarginPx = 1.0;
// Frame gradients below this (sum of the absolute central differences, grey levels) carry no pose.
constexpr float kMinStrength = 2.0f;
// The blur term: the footprint widened by this factor adds (kWiden^2 - 1) / 12 px^2 of variance.
constexpr double kWiden = 2.0;
constexpr double kWidenVariance = (kWiden * kWiden - 1.0) / 12.0;

// Template px (texel edges at integers) -> frame px of the undistorted image, for pose T.
Eigen::Matrix3d template_to_frame(const Eigen::Isometry3d& T, double fx, double fy, double cx, double cy, double width_m,
                                  double height_m, int tw, int th) {
  Eigen::Matrix3d S;
  S << width_m / tw, 0, -0.5 * width_m, 0, height_m / th, -0.5 * height_m, 0, 0, 1;
  Eigen::Matrix3d K;
  K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  Eigen::Matrix3d M;
  M << T.linear().col(0), T.linear().col(1), T.translation();
  return K * M * S;
}

}  // namespace

AreaPoseRefiner::AreaPoseRefiner(const cv::Mat& template_image, double width_m, double height_m, const PinholeCamera& camera,
                                 const Se3RefinerSettings& settings)
    : width_m_(width_m),
      height_m_(height_m),
      camera_(camera),
      fx_(camera.intrinsics().fx),
      fy_(camera.intrinsics().fy),
      cx_(camera.intrinsics().cx),
      cy_(camera.intrinsics().cy),
      settings_(settings) {
  if (template_image.empty() || template_image.type() != CV_8UC1) {
    throw std::invalid_argument("AreaPoseRefiner: the template must be a non-empty CV_8UC1 image");
  }
  if (!(width_m > 0) || !(height_m > 0) || !(fx_ > 0) || !(fy_ > 0)) {
    throw std::invalid_argument("AreaPoseRefiner: the panel size and the focal lengths must be positive");
  }
  tw_ = template_image.cols;
  th_ = template_image.rows;
  cv::integral(template_image, sat_, CV_64F);
  if (camera.has_distortion()) {
    // Each raw pixel's undistorted position, once (the lens does not move).
    undistorted_of_raw_.create(camera.height(), camera.width(), CV_32FC2);
    for (int y = 0; y < camera.height(); ++y) {
      auto* row = undistorted_of_raw_.ptr<cv::Vec2f>(y);
      for (int x = 0; x < camera.width(); ++x) {
        const Eigen::Vector2d n = camera.undistort(Eigen::Vector2d((x - cx_) / fx_, (y - cy_) / fy_));
        row[x] = cv::Vec2f(static_cast<float>(fx_ * n.x() + cx_), static_cast<float>(fy_ * n.y() + cy_));
      }
    }
  }
}

Eigen::Vector2f AreaPoseRefiner::undistorted_at(int x, int y) const {
  if (undistorted_of_raw_.empty()) return {static_cast<float>(x), static_cast<float>(y)};
  const cv::Vec2f& v = undistorted_of_raw_.at<cv::Vec2f>(y, x);
  return {v[0], v[1]};
}

double AreaPoseRefiner::box_mean(double x0, double y0, double x1, double y1) const {
  // The integral of piecewise-constant texels is bilinear within a texel: bilinear reads of the table
  // are exact. The box's corners share their columns and rows.
  const int i0 = std::min(static_cast<int>(x0), tw_ - 1), i1 = std::min(static_cast<int>(x1), tw_ - 1);
  const int j0 = std::min(static_cast<int>(y0), th_ - 1), j1 = std::min(static_cast<int>(y1), th_ - 1);
  const double fx0 = x0 - i0, fx1 = x1 - i1, fy0 = y0 - j0, fy1 = y1 - j1;
  // The integral along table row r from column x0 to x1.
  const auto row_span = [&](int r) {
    const double* row = sat_.ptr<double>(r);
    return (row[i1] + fx1 * (row[i1 + 1] - row[i1])) - (row[i0] + fx0 * (row[i0 + 1] - row[i0]));
  };
  const double a0 = row_span(j0), a1 = row_span(j0 + 1), b0 = row_span(j1), b1 = row_span(j1 + 1);
  return ((b0 + fy1 * (b1 - b0)) - (a0 + fy0 * (a1 - a0))) / ((x1 - x0) * (y1 - y0));
}

bool AreaPoseRefiner::select(const cv::Mat& raw, const Eigen::Isometry3d& T) const {
  samples_.clear();
  candidates_.clear();
  if (raw.empty() || raw.type() != CV_8UC1 || raw.cols != camera_.width() || raw.rows != camera_.height()) return false;
  const Eigen::Matrix3d G = template_to_frame(T, fx_, fy_, cx_, cy_, width_m_, height_m_, tw_, th_);
  const Eigen::Matrix3d Ginv = G.inverse();
  // The panel's raw bounding box: points along its outline through the lens (barrel distortion bows
  // the edges).
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  constexpr int kOutline = 8;
  for (int k = 0; k < 4 * kOutline; ++k) {
    const int side = k / kOutline;
    const double f = static_cast<double>(k % kOutline) / kOutline;
    const double sx = side == 0 ? f : side == 1 ? 1.0 : side == 2 ? 1.0 - f : 0.0;
    const double sy = side == 0 ? 0.0 : side == 1 ? f : side == 2 ? 1.0 : 1.0 - f;
    const Eigen::Vector3d P = T * Eigen::Vector3d((sx - 0.5) * width_m_, (sy - 0.5) * height_m_, 0);
    const auto px = camera_.project(P);
    if (!px) return false;
    x0 = std::min(x0, px->x()), x1 = std::max(x1, px->x()), y0 = std::min(y0, px->y()), y1 = std::max(y1, px->y());
  }
  const int left = std::max(2, static_cast<int>(std::floor(x0))), right = std::min(raw.cols - 3, static_cast<int>(std::ceil(x1)));
  const int top = std::max(2, static_cast<int>(std::floor(y0))), bottom = std::min(raw.rows - 3, static_cast<int>(std::ceil(y1)));
  if (right - left < 4 || bottom - top < 4) return false;
  // Template px per frame px at the panel's centre, for the edge margin (the widened footprint's
  // pixel, kEdgeMarginPx, and a pixel for the gradient's neighbours).
  const Eigen::Vector3d centre = G * Eigen::Vector3d(0.5 * tw_, 0.5 * th_, 1);
  const Eigen::Vector3d right_of = G * Eigen::Vector3d(0.5 * tw_ + 1, 0.5 * th_, 1);
  const Eigen::Vector3d below = G * Eigen::Vector3d(0.5 * tw_, 0.5 * th_ + 1, 1);
  const double px_per_tx = (right_of.head<2>() / right_of.z() - centre.head<2>() / centre.z()).norm();
  const double px_per_ty = (below.head<2>() / below.z() - centre.head<2>() / centre.z()).norm();
  if (!(px_per_tx > 0) || !(px_per_ty > 0)) return false;
  const double reach = 1.5 + kEdgeMarginPx + 0.5;  // + 0.5: the lens's local stretch
  const double mx = reach / px_per_tx, my = reach / px_per_ty;
  // A near panel covers tens of thousands of pixels: scan a sub-grid with about 4 candidates per
  // pixel to be kept.
  const double box = static_cast<double>(right - left + 1) * static_cast<double>(bottom - top + 1);
  const int stride = std::max(1, static_cast<int>(std::sqrt(box / (4.0 * std::max(1, settings_.max_samples)))));
  for (int y = top; y <= bottom; y += stride) {
    const uchar* r = raw.ptr<uchar>(y);
    for (int x = left; x <= right; x += stride) {
      const Eigen::Vector2f pu = undistorted_at(x, y);
      const Eigen::Vector3d q = Ginv * Eigen::Vector3d(pu.x(), pu.y(), 1.0);
      if (!(q.z() > 1e-12)) continue;
      const double cu = q.x() / q.z(), cv = q.y() / q.z();
      if (cu < mx || cv < my || cu > tw_ - mx || cv > th_ - my) continue;
      const float strength = static_cast<float>(std::abs(r[x + 1] - r[x - 1]) +
                                                std::abs(raw.ptr<uchar>(y + 1)[x] - raw.ptr<uchar>(y - 1)[x]));
      if (strength < kMinStrength) continue;
      const int cell = std::min(kCells - 1, static_cast<int>(cu * kCells / tw_)) +
                       kCells * std::min(kCells - 1, static_cast<int>(cv * kCells / th_));
      candidates_.push_back({x, y, cell, strength});
    }
  }
  // By cell (a counting sort), then each cell's strongest quota.
  std::array<int, kCells * kCells + 1> start{};
  for (const Candidate& c : candidates_) ++start[static_cast<std::size_t>(c.cell) + 1];
  for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  by_cell_.resize(candidates_.size());
  std::array<int, kCells * kCells> fill{};
  for (const Candidate& c : candidates_) {
    const auto cell = static_cast<std::size_t>(c.cell);
    by_cell_[static_cast<std::size_t>(start[cell] + fill[cell]++)] = c;
  }
  const int quota = std::max(1, settings_.max_samples / (kCells * kCells));
  for (std::size_t cell = 0; cell + 1 < start.size(); ++cell) {
    const int begin = start[cell], end = start[cell + 1];
    if (end <= begin) continue;
    float threshold = 0;
    if (end - begin > quota) {
      cell_strengths_.clear();
      for (int k = begin; k < end; ++k) cell_strengths_.push_back(by_cell_[static_cast<std::size_t>(k)].strength);
      const auto nth = cell_strengths_.begin() + (quota - 1);
      std::nth_element(cell_strengths_.begin(), nth, cell_strengths_.end(), std::greater<float>());
      threshold = *nth;
    }
    int taken = 0;
    for (int k = begin; k < end && taken < quota; ++k) {
      const Candidate& c = by_cell_[static_cast<std::size_t>(k)];
      if (c.strength < threshold) continue;
      Sample s;
      s.x = c.x;
      s.y = c.y;
      s.grey = raw.at<uchar>(c.y, c.x);
      s.pu = undistorted_at(c.x, c.y);
      s.D.col(0) = 0.5f * (undistorted_at(c.x + 1, c.y) - undistorted_at(c.x - 1, c.y));
      s.D.col(1) = 0.5f * (undistorted_at(c.x, c.y + 1) - undistorted_at(c.x, c.y - 1));
      const uchar* row = raw.ptr<uchar>(c.y);
      const Eigen::Vector2f g_raw(0.5f * static_cast<float>(row[c.x + 1] - row[c.x - 1]),
                                  0.5f * static_cast<float>(raw.ptr<uchar>(c.y + 1)[c.x] - raw.ptr<uchar>(c.y - 1)[c.x]));
      s.gradient = s.D.inverse().transpose() * g_raw;
      // The footprint: the pixel square through the lens and the inverse homography, as a box with
      // its second moments along the template's axes.
      const Eigen::Vector3d q = Ginv * Eigen::Vector3d(s.pu.x(), s.pu.y(), 1.0);
      const double cu = q.x() / q.z(), cv = q.y() / q.z();
      Eigen::Matrix2d dc_dpu;  // d(template px) / d(undistorted px)
      dc_dpu << (Ginv(0, 0) - cu * Ginv(2, 0)) / q.z(), (Ginv(0, 1) - cu * Ginv(2, 1)) / q.z(),
          (Ginv(1, 0) - cv * Ginv(2, 0)) / q.z(), (Ginv(1, 1) - cv * Ginv(2, 1)) / q.z();
      const Eigen::Matrix2d A = dc_dpu * s.D.cast<double>();  // d(template px) / d(raw px)
      s.hx = static_cast<float>(0.5 * A.row(0).norm());
      s.hy = static_cast<float>(0.5 * A.row(1).norm());
      samples_.push_back(s);
      ++taken;
    }
  }
  return static_cast<int>(samples_.size()) >= kMinPixels;
}

PhotometricNormal AreaPoseRefiner::accumulate(const Eigen::Isometry3d& T, const PanelAppearance& a) const {
  PhotometricNormal n;
  const Eigen::Matrix3d G = template_to_frame(T, fx_, fy_, cx_, cy_, width_m_, height_m_, tw_, th_);
  const Eigen::Matrix3d Ginv = G.inverse();
  const Eigen::Vector3d r1 = T.linear().col(0), r2 = T.linear().col(1), t = T.translation();
  PhotometricVector J;
  for (const Sample& s : samples_) {
    // The template point seen at the pixel.
    const Eigen::Vector3d q = Ginv * Eigen::Vector3d(s.pu.x(), s.pu.y(), 1.0);
    if (!(q.z() > 1e-12)) continue;
    const double iqz = 1.0 / q.z();
    const double cu = q.x() * iqz, cv = q.y() * iqz;
    const double hx = s.hx, hy = s.hy;
    // The widened footprint must lie on the panel (see kEdgeMarginPx).
    const double mx = hx * (kWiden + 2.0 * kEdgeMarginPx), my = hy * (kWiden + 2.0 * kEdgeMarginPx);
    if (cu < mx || cv < my || cu > tw_ - mx || cv > th_ - my) continue;
    // The prediction, and its change per px^2 of extra blur variance: the footprint widened by
    // kWiden (a box of half a pixel has a variance of 1/12 px^2 per axis).
    const double P = box_mean(cu - hx, cv - hy, cu + hx, cv + hy);
    const double Q = (box_mean(cu - kWiden * hx, cv - kWiden * hy, cu + kWiden * hx, cv + kWiden * hy) - P) / kWidenVariance;
    const Eigen::Vector2d g = s.gradient.cast<double>();
    const double X = cu * width_m_ / tw_ - 0.5 * width_m_, Y = cv * height_m_ / th_ - 0.5 * height_m_;
    const Eigen::Vector3d Pc = X * r1 + Y * r2 + t;
    const double iz = 1.0 / Pc.z();
    const double px = X / (0.5 * width_m_), py = Y / (0.5 * height_m_);
    const double gain = a.gain + a.gain_x * px + a.gain_y * py;
    const double model = P + a.blur * Q;
    const double residual = s.grey - gain * model - a.bias;
    // The prediction moves with the plane: d(prediction at p)/dxi = -grad . dp/dxi, and the residual
    // has -gain times it; gain times the prediction's gradient is the frame's (read once per frame).
    const Eigen::Vector3d dP(g.x() * fx_ * iz, g.y() * fy_ * iz, -(g.x() * fx_ * Pc.x() + g.y() * fy_ * Pc.y()) * iz * iz);
    J.head<3>() = Pc.cross(dP);
    J.segment<3>(3) = dP;
    J[6] = -model;
    J[7] = -model * px;
    J[8] = -model * py;
    J[9] = -1.0;
    J[kBlurParam] = settings_.estimate_blur ? -gain * Q : 0.0;
    n.JtJ.noalias() += J * J.transpose();
    n.Jtr += J * residual;
    n.ssr += residual * residual;
    n.sum_grey += s.grey;
    n.sum_grey2 += static_cast<double>(s.grey) * s.grey;
    ++n.valid;
  }
  if (!settings_.estimate_blur) n.JtJ(kBlurParam, kBlurParam) = 1.0;
  return n;
}

Se3Refinement AreaPoseRefiner::refine(const cv::Mat& raw, const Eigen::Isometry3d& T_start) const {
  if (!select(raw, T_start)) {
    Se3Refinement out;
    out.T_cam_object = T_start;
    out.failure = raw.empty() || raw.type() != CV_8UC1 || raw.cols != camera_.width() || raw.rows != camera_.height()
                      ? "frame is not a CV_8UC1 image of the camera's size"
                      : "too little of the panel in view";
    return out;
  }
  return refine(T_start);
}

Se3Refinement AreaPoseRefiner::refine(const Eigen::Isometry3d& T_start, const Eigen::Isometry3d* warm_start) const {
  Se3Refinement out;
  out.T_cam_object = T_start;
  if (static_cast<int>(samples_.size()) < kMinPixels) {
    out.failure = "too little of the panel in view";
    return out;
  }
  const int needed = std::max(kMinPixels, static_cast<int>(samples_.size()) / 2);
  const GaussNewtonRun run = run_gauss_newton(
      warm_start != nullptr ? *warm_start : T_start,
      [&](const Eigen::Isometry3d& T, const PanelAppearance& a) { return accumulate(T, a); }, needed,
      ResidualComparison::Mean, settings_.max_iterations, settings_.convergence_px, width_m_, height_m_, fx_, fy_);
  if (!finish_refinement(run, T_start, settings_.max_corner_shift_px, width_m_, height_m_, fx_, fy_, cx_, cy_,
                         cv::Size(camera_.width(), camera_.height()), settings_, out)) {
    return out;
  }
  out.blur_variance_px2 = 2.0 * run.appearance.blur;
  return out;
}

}  // namespace labo::planar
