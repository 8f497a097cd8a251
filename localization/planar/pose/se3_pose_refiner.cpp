#include "localization/planar/pose/se3_pose_refiner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "localization/planar/bilinear_sample.hpp"
#include "localization/planar/track/homography_tracker.hpp"
#include "localization/planar/pose/photometric_gauss_newton.hpp"

namespace labo::planar {

namespace {

constexpr int kMinLevelSidePx = 16;
constexpr int kBorderPx = 2;   // template pixels this close to the edge see the outside in the frame
constexpr int kCells = 6;      // per side: the samples are spread over the panel (perspective leverage)
constexpr int kMinSamples = 50;
// At range the template is area-resampled to kOversampling times the panel's apparent size (template
// px per frame px at the panel's centre), and blurred to the frame's blur, instead of the pyramid
// level: the pyramid's 2x steps leave the template 0.6-0.9 or 1.1-1.3 frame px per px and its blur off
// by as much. Not exactly 1: then every sample has the same sub-pixel phase in the frame and the
// bilinear interpolation's phase-dependent bias no longer averages out over the panel (worse than the
// pyramid); not a simple ratio either (2: two phases). Only while the panel appears smaller than
// kResampleBelow times the working template (nearer, the pyramid does better on the synthetic
// sequences). docs/planar.md, "the template at the frame's resolution".
constexpr double kOversampling = 1.3;
constexpr double kResampleBelow = 0.5;
// The resampled template is rebuilt when the panel's apparent width or height changes by more than
// this ratio (an approach at 1 m/s from 2.5 m: every ~3 frames).
constexpr double kRebuildRatio = 0.02;
// How much farther than max_corner_shift_px a corner may move when a blur is modelled (half the blur,
// at most this): the smoothed region is grown by it.
constexpr double kMaxBlurLeashPx = 6.0;
constexpr int kBlurParam = kPhotometricBlurParam;  // fixed at 0 unless estimate_blur

// Bilinear value of a CV_32FC1 image (no bounds check, as bilinear_grey).
double bilinear_float(const cv::Mat& image, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = image.ptr<float>(y0) + x0;
  const float* r1 = image.ptr<float>(y0 + 1) + x0;
  const double top = r0[0] + fx * (r0[1] - r0[0]);
  const double bottom = r1[0] + fx * (r1[1] - r1[0]);
  return top + fy * (bottom - top);
}

}  // namespace

Se3PoseRefiner::Se3PoseRefiner(const cv::Mat& working_template, double width_m, double height_m, const cv::Matx33d& K,
                               const Se3RefinerSettings& settings)
    : template_size_(working_template.size()),
      width_m_(width_m),
      height_m_(height_m),
      fx_(K(0, 0)),
      fy_(K(1, 1)),
      cx_(K(0, 2)),
      cy_(K(1, 2)),
      settings_(settings) {
  if (settings_.smoothing_sigma_px > 0) frame_blur_ = GaussianBlur8u(settings_.smoothing_sigma_px);
  working_ = working_template;
  if (working_template.empty() || working_template.type() != CV_8UC1) {
    throw std::invalid_argument("Se3PoseRefiner: the template must be a non-empty CV_8UC1 image");
  }
  if (!(width_m > 0) || !(height_m > 0) || !(fx_ > 0) || !(fy_ > 0)) {
    throw std::invalid_argument("Se3PoseRefiner: the panel size and the focal lengths must be positive");
  }
  cv::Mat level = working_template;
  for (int k = 0; std::min(level.cols, level.rows) >= kMinLevelSidePx; ++k) {
    add_level(level, k);
    cv::Mat next;
    cv::pyrDown(level, next);
    level = next;
  }
}

void Se3PoseRefiner::select_samples(const cv::Mat& gray, const cv::Mat& magnitude, const cv::Mat& laplacian, double mx,
                                    double my, double bx, double by, int border, std::vector<float>& strengths, std::vector<Sample>& out) const {
  const int quota = std::max(1, settings_.max_samples / (kCells * kCells));
  out.clear();
  for (int cy = 0; cy < kCells; ++cy) {
    for (int cx = 0; cx < kCells; ++cx) {
      const int y0 = std::max(border, cy * gray.rows / kCells);
      const int y1 = std::min(gray.rows - border, (cy + 1) * gray.rows / kCells);
      const int x0 = std::max(border, cx * gray.cols / kCells);
      const int x1 = std::min(gray.cols - border, (cx + 1) * gray.cols / kCells);
      strengths.clear();
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) strengths.push_back(magnitude.at<float>(y, x));
      }
      if (strengths.empty()) continue;
      // The cell's quota-th strongest gradient is its threshold (flat cells contribute nothing).
      const auto nth = strengths.begin() + std::min<std::ptrdiff_t>(quota, static_cast<std::ptrdiff_t>(strengths.size())) - 1;
      std::nth_element(strengths.begin(), nth, strengths.end(), std::greater<float>());
      const float threshold = std::max(*nth, 8.0f);  // Sobel units: ~1 grey level per pixel
      int taken = 0;
      for (int y = y0; y < y1 && taken < quota; ++y) {
        for (int x = x0; x < x1 && taken < quota; ++x) {
          if (magnitude.at<float>(y, x) < threshold) continue;
          out.push_back({static_cast<float>(x * mx + bx), static_cast<float>(y * my + by),
                         static_cast<float>(gray.at<uchar>(y, x)), static_cast<float>(x), static_cast<float>(y),
                         laplacian.at<float>(y, x)});
          ++taken;
        }
      }
    }
  }
}

void Se3PoseRefiner::add_level(const cv::Mat& level, int k) {
  cv::Mat gray = level;
  if (settings_.smoothing_sigma_px > 0) cv::GaussianBlur(level, gray, cv::Size(0, 0), settings_.smoothing_sigma_px);
  cv::Mat gx, gy, magnitude;
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3);
  cv::magnitude(gx, gy, magnitude);
  cv::Mat laplacian;
  cv::Laplacian(gray, laplacian, CV_32F, 1);
  // Level-k pixel i is centred on working pixel i * 2^k (cv::pyrDown keeps every other pixel).
  const double step = std::ldexp(1.0, k);
  const double mx = width_m_ / template_size_.width, my = height_m_ / template_size_.height;
  std::vector<Sample> samples;
  std::vector<float> strengths;
  select_samples(gray, magnitude, laplacian, step * mx, step * my, 0.5 * mx - 0.5 * width_m_, 0.5 * my - 0.5 * height_m_,
                 kBorderPx, strengths, samples);
  if (static_cast<int>(samples.size()) < kMinSamples) return;  // coarser levels have even less
  if (static_cast<int>(levels_.size()) == k) {
    levels_.push_back(std::move(samples));
    level_images_.push_back(gray.clone());
    level_laplacians_.push_back(laplacian);
  }
}

void Se3PoseRefiner::blur_samples(const View& view, const Eigen::Isometry3d& T, const Eigen::Vector2d& blur_px,
                                  std::vector<float>& out, std::vector<float>& out_laplacian) const {
  const std::vector<Sample>& samples = *view.samples;
  const cv::Mat& image = *view.image;
  // Image px per view px at the panel's centre: the projection's Jacobian times metres per view px.
  const Eigen::Vector3d P = T.translation();
  const Eigen::Vector3d r1 = T.linear().col(0) * view.mx, r2 = T.linear().col(1) * view.my;
  Eigen::Matrix2d J;
  for (int c = 0; c < 2; ++c) {
    const Eigen::Vector3d d = c == 0 ? r1 : r2;
    J(0, c) = fx_ * (d.x() * P.z() - P.x() * d.z()) / (P.z() * P.z());
    J(1, c) = fy_ * (d.y() * P.z() - P.y() * d.z()) / (P.z() * P.z());
  }
  const Eigen::Vector2d delta = J.inverse() * blur_px;  // the blur in view px
  const int taps = std::clamp(static_cast<int>(std::ceil(delta.norm())) + 1, 2, 16);
  const double x_max = image.cols - 1.001, y_max = image.rows - 1.001;
  const bool with_laplacian = settings_.estimate_blur;
  out.resize(samples.size());
  out_laplacian.resize(with_laplacian ? samples.size() : 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    double sum = 0, sum_laplacian = 0;
    for (int k = 0; k < taps; ++k) {
      const double f = -0.5 + static_cast<double>(k) / (taps - 1);
      const double x = std::clamp(samples[i].lx + f * delta.x(), 0.0, x_max);
      const double y = std::clamp(samples[i].ly + f * delta.y(), 0.0, y_max);
      sum += bilinear_grey(image, x, y);
      if (with_laplacian) sum_laplacian += bilinear_float(*view.laplacian, x, y);
    }
    out[i] = static_cast<float>(sum / taps);
    if (with_laplacian) out_laplacian[i] = static_cast<float>(sum_laplacian / taps);
  }
}

Se3PoseRefiner::View Se3PoseRefiner::view_for(const Eigen::Isometry3d& T) const {
  const auto level_view = [&](int level) {
    const double step = std::ldexp(1.0, level);
    return View{&levels_[static_cast<std::size_t>(level)], &level_images_[static_cast<std::size_t>(level)],
                &level_laplacians_[static_cast<std::size_t>(level)], step * width_m_ / template_size_.width, step * height_m_ / template_size_.height};
  };
  if (!settings_.resample_to_frame) return level_view(level_for(T));
  // The panel's apparent size: frame px per metre along its x and y at its centre, times its size.
  const Eigen::Vector3d P = T.translation();
  if (!(P.z() > 1e-3)) return level_view(level_for(T));
  const auto px_per_m = [&](const Eigen::Vector3d& d) {
    return std::hypot(fx_ * (d.x() * P.z() - P.x() * d.z()), fy_ * (d.y() * P.z() - P.y() * d.z())) / (P.z() * P.z());
  };
  const double target_w = kOversampling * width_m_ * px_per_m(T.linear().col(0));
  const double target_h = kOversampling * height_m_ * px_per_m(T.linear().col(1));
  if (!(target_w < kResampleBelow * template_size_.width && target_h < template_size_.height)) {
    return level_view(level_for(T));
  }
  Resampled& r = resampled_;
  const bool fresh = r.size.area() > 0 && std::abs(target_w / r.target_w - 1) <= kRebuildRatio &&
                     std::abs(target_h / r.target_h - 1) <= kRebuildRatio;
  if (!fresh) {
    const cv::Size size(std::clamp(static_cast<int>(std::lround(target_w)), kMinLevelSidePx, template_size_.width),
                        std::clamp(static_cast<int>(std::lround(target_h)), kMinLevelSidePx, template_size_.height));
    const std::size_t capacity = static_cast<std::size_t>(template_size_.area());
    if (r.area.size() < capacity) {  // once: every later size fits
      r.area.resize(capacity);
      r.smoothed.resize(capacity);
      r.gx.resize(capacity);
      r.gy.resize(capacity);
      r.magnitude.resize(capacity);
      r.laplacian.resize(capacity);
      r.strengths.reserve(capacity);
      r.samples.reserve(static_cast<std::size_t>(settings_.max_samples) + kCells * kCells);
    }
    // Headers over the buffers, each a whole image (no neighbours outside it for the filters to read).
    cv::Mat area(size, CV_8UC1, r.area.data()), smoothed(size, CV_8UC1, r.smoothed.data());
    cv::Mat gx(size, CV_32FC1, r.gx.data()), gy(size, CV_32FC1, r.gy.data()), magnitude(size, CV_32FC1, r.magnitude.data());
    // Area averaging, as a camera's pixel integrates the panel (an explicit size: the exact scale is
    // the ratio of the sizes, used below for the samples' positions).
    cv::resize(working_, area, size, 0, 0, cv::INTER_AREA);
    // The frame's blur in its own pixels: the pixel's box (variance 1/12) and the smoothing Gaussian;
    // the area resampling already gave the template a box of 1/k frame px, the Gaussian adds the rest
    // (in template px, k per frame px).
    const double sigma = settings_.smoothing_sigma_px;
    const double sigma_template =
        kOversampling * std::sqrt(sigma * sigma + (1 - 1 / (kOversampling * kOversampling)) / 12);
    if (sigma > 0) {
      cv::GaussianBlur(area, smoothed, cv::Size(0, 0), sigma_template);
    } else {
      area.copyTo(smoothed);
    }
    cv::Sobel(smoothed, gx, CV_32F, 1, 0, 3);
    cv::Sobel(smoothed, gy, CV_32F, 0, 1, 3);
    cv::magnitude(gx, gy, magnitude);
    cv::Mat laplacian(size, CV_32FC1, r.laplacian.data());
    cv::Laplacian(smoothed, laplacian, CV_32F, 1);
    const double mx = width_m_ / size.width, my = height_m_ / size.height;
    select_samples(smoothed, magnitude, laplacian, mx, my, 0.5 * mx - 0.5 * width_m_, 0.5 * my - 0.5 * height_m_, kBorderPx,
                   r.strengths, r.samples);
    r.size = static_cast<int>(r.samples.size()) >= kMinSamples ? size : cv::Size();
    r.target_w = target_w;
    r.target_h = target_h;
    ++r.builds;
  }
  if (r.size.area() == 0) return level_view(level_for(T));  // too little texture at that size
  r.image = cv::Mat(r.size, CV_8UC1, r.smoothed.data());     // a header (also right in a copy of this refiner)
  r.laplacian_image = cv::Mat(r.size, CV_32FC1, r.laplacian.data());
  return View{&r.samples, &r.image, &r.laplacian_image, width_m_ / r.size.width, height_m_ / r.size.height};
}

int Se3PoseRefiner::level_for(const Eigen::Isometry3d& T) const {
  // The homography working template px -> image px of this pose, for the tracker's level rule.
  const Eigen::Matrix3d& R = T.linear();
  const Eigen::Vector3d& t = T.translation();
  Eigen::Matrix3d K;
  K << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1;
  Eigen::Matrix3d S;
  const double mx = width_m_ / template_size_.width, my = height_m_ / template_size_.height;
  S << mx, 0, 0.5 * mx - 0.5 * width_m_, 0, my, 0.5 * my - 0.5 * height_m_, 0, 0, 1;
  Eigen::Matrix3d P;
  P << R.col(0), R.col(1), t;
  Eigen::Matrix3d H = K * P * S;
  cv::Matx33d Hc;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) Hc(i, j) = H(i, j);
  }
  return matching_template_level(Hc, template_size_, static_cast<int>(levels_.size()) - 1);
}

void Se3PoseRefiner::smooth(const cv::Mat& undistorted, std::initializer_list<Eigen::Isometry3d> poses,
                            SmoothedFrame& out) const {
  const cv::Rect whole(0, 0, undistorted.cols, undistorted.rows);
  if (!(settings_.smoothing_sigma_px > 0) || undistorted.empty()) {
    out.image = undistorted;  // a header: no copy
    out.valid = whole;
    return;
  }
  // Reach: the refinement may move a corner by max_corner_shift_px, the gradient reads 1 px either
  // side, and the Gaussian needs 3 sigma of real neighbours.
  const double reach = settings_.max_corner_shift_px + kMaxBlurLeashPx + 2.0 + 3.0 * settings_.smoothing_sigma_px;
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const Eigen::Isometry3d& T : poses) {
    for (double sx : {-0.5, 0.5}) {
      for (double sy : {-0.5, 0.5}) {
        const Eigen::Vector3d P = T * Eigen::Vector3d(sx * width_m_, sy * height_m_, 0);
        if (!(P.z() > 1e-3)) {  // a corner behind the camera: smooth everything
          x0 = y0 = -1e9;
          x1 = y1 = 1e9;
          continue;
        }
        const double u = fx_ * P.x() / P.z() + cx_, v = fy_ * P.y() / P.z() + cy_;
        x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v);
      }
    }
  }
  const auto clamp_to = [](double value, int hi) { return static_cast<int>(std::clamp(value, 0.0, static_cast<double>(hi))); };
  const int left = clamp_to(std::floor(x0 - reach), undistorted.cols), right = clamp_to(std::ceil(x1 + reach) + 1, undistorted.cols);
  const int top = clamp_to(std::floor(y0 - reach), undistorted.rows), bottom = clamp_to(std::ceil(y1 + reach) + 1, undistorted.rows);
  out.valid = cv::Rect(left, top, std::max(0, right - left), std::max(0, bottom - top)) & whole;
  out.image.create(undistorted.size(), CV_8UC1);
  if (out.valid.area() == 0) return;
  // A region of interest: the blur reads the real neighbours outside it (reflects only at the frame's border).
  if (out.valid != whole) {
    frame_blur_.apply(undistorted, out.valid, out.image, out.blur_rows);  // cv::GaussianBlur's pixels, no allocation
  } else {
    // The whole frame (a panel filling it): OpenCV blurs a whole image by its fixed-point path, which
    // GaussianBlur8u does not reproduce; rare, and it allocates.
    cv::GaussianBlur(undistorted, out.image, cv::Size(0, 0), settings_.smoothing_sigma_px);
  }
}

PhotometricNormal Se3PoseRefiner::accumulate(const std::vector<Sample>& samples, const float* values, const float* laplacians,
                                             const SmoothedFrame& frame, const Eigen::Isometry3d& T,
                                             const PanelAppearance& a) const {
  PhotometricNormal n;
  const cv::Mat& image = frame.image;
  const Eigen::Vector3d r1 = T.linear().col(0), r2 = T.linear().col(1), t = T.translation();
  // Bilinear reads at u +- 1 stay inside the smoothed region.
  const double x_min = frame.valid.x + 1, y_min = frame.valid.y + 1;
  const double x_max = frame.valid.x + frame.valid.width - 2, y_max = frame.valid.y + frame.valid.height - 2;
  PhotometricVector J;
  const double sx = 2.0 / width_m_, sy = 2.0 / height_m_;  // panel coordinates in [-1, 1]
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    const double sharp_grey = values != nullptr ? values[i] : s.t;
    const double laplacian = laplacians != nullptr ? laplacians[i] : s.laplacian;
    const double template_grey = sharp_grey + a.blur * laplacian;
    const Eigen::Vector3d P = s.X * r1 + s.Y * r2 + t;
    if (!(P.z() > 1e-3)) continue;
    const double iz = 1.0 / P.z();
    const double u = fx_ * P.x() * iz + cx_, v = fy_ * P.y() * iz + cy_;
    if (!(u >= x_min && v >= y_min && u < x_max && v < y_max)) continue;
    const double value = bilinear_grey(image, u, v);
    const double gu = 0.5 * (bilinear_grey(image, u + 1, v) - bilinear_grey(image, u - 1, v));
    const double gv = 0.5 * (bilinear_grey(image, u, v + 1) - bilinear_grey(image, u, v - 1));
    // d(grey)/dP through the projection, then dP/d(omega, v) = [-[P]x, I].
    const Eigen::Vector3d dP(gu * fx_ * iz, gv * fy_ * iz, -(gu * fx_ * P.x() + gv * fy_ * P.y()) * iz * iz);
    J.head<3>() = P.cross(dP);
    J.segment<3>(3) = dP;
    const double x = s.X * sx, y = s.Y * sy;
    J[6] = -template_grey;
    J[7] = -template_grey * x;
    J[8] = -template_grey * y;
    J[9] = -1.0;
    const double gain = a.gain + a.gain_x * x + a.gain_y * y;
    J[kBlurParam] = settings_.estimate_blur ? -gain * laplacian : 0.0;
    const double residual = value - gain * template_grey - a.bias;
    n.JtJ.selfadjointView<Eigen::Lower>().rankUpdate(J);
    n.Jtr += J * residual;
    n.ssr += residual * residual;
    n.sum_grey += value;
    n.sum_grey2 += value * value;
    ++n.valid;
  }
  n.JtJ.triangularView<Eigen::StrictlyUpper>() = n.JtJ.transpose();
  if (!settings_.estimate_blur) n.JtJ(kBlurParam, kBlurParam) = 1.0;  // the blur stays 0
  return n;
}

Se3Refinement Se3PoseRefiner::refine(const cv::Mat& undistorted, const Eigen::Isometry3d& T_start) const {
  if (undistorted.empty() || undistorted.type() != CV_8UC1) {
    Se3Refinement out;
    out.T_cam_object = T_start;
    out.failure = "frame is not a non-empty CV_8UC1 image";
    return out;
  }
  SmoothedFrame frame;
  smooth(undistorted, {T_start}, frame);
  return refine(frame, T_start);
}

Se3Refinement Se3PoseRefiner::refine(const SmoothedFrame& frame, const Eigen::Isometry3d& T_start,
                                     const Eigen::Vector2d& blur_px, const Eigen::Isometry3d* warm_start) const {
  const cv::Mat& undistorted = frame.image;
  Se3Refinement out;
  out.T_cam_object = T_start;
  if (levels_.empty()) {
    out.failure = "template too small";
    return out;
  }
  if (undistorted.empty() || undistorted.type() != CV_8UC1) {
    out.failure = "frame is not a non-empty CV_8UC1 image";
    return out;
  }
  const View view = view_for(T_start);
  const std::vector<Sample>& samples = *view.samples;
  last_template_size_ = view.image->size();
  const float* values = nullptr;
  const float* laplacians = nullptr;
  if (blur_px.allFinite() && blur_px.norm() >= 0.5) {
    blur_samples(view, T_start, blur_px, frame.blurred_template, frame.blurred_laplacian);
    values = frame.blurred_template.data();
    if (settings_.estimate_blur) laplacians = frame.blurred_laplacian.data();
  }
  const int needed = std::max(kMinSamples, static_cast<int>(samples.size()) / 2);
  const GaussNewtonRun run = run_gauss_newton(
      warm_start != nullptr ? *warm_start : T_start,
      [&](const Eigen::Isometry3d& T, const PanelAppearance& a) { return accumulate(samples, values, laplacians, frame, T, a); },
      needed, ResidualComparison::Sum, settings_.max_iterations, settings_.convergence_px, width_m_, height_m_, fx_, fy_);
  // A blurred frame pulls the tracker's corners along the blur: the modelled blur widens the leash.
  const double blur_leash_px = values != nullptr ? std::min(kMaxBlurLeashPx, 0.5 * blur_px.norm()) : 0.0;
  if (!finish_refinement(run, T_start, settings_.max_corner_shift_px + blur_leash_px, width_m_, height_m_, fx_, fy_, cx_, cy_,
                         undistorted.size(), settings_, out)) {
    return out;
  }
  // Frame px per template-view px at the panel's centre (mean of the two directions).
  const double z = std::max(1e-3, run.T.translation().z());
  const double scale = 0.5 * (fx_ * view.mx + fy_ * view.my) / z;
  out.blur_variance_px2 = 2.0 * run.appearance.blur * scale * scale;
  return out;
}

}  // namespace labo::planar

