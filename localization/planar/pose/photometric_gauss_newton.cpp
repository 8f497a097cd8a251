#include "localization/planar/pose/photometric_gauss_newton.hpp"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace labo::planar {

double max_corner_shift_px(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double width_m, double height_m,
                           double fx, double fy) {
  const std::array<Eigen::Vector3d, 4> corners{Eigen::Vector3d(-0.5 * width_m, -0.5 * height_m, 0),
                                               Eigen::Vector3d(0.5 * width_m, -0.5 * height_m, 0),
                                               Eigen::Vector3d(0.5 * width_m, 0.5 * height_m, 0),
                                               Eigen::Vector3d(-0.5 * width_m, 0.5 * height_m, 0)};
  double shift = 0;
  for (const auto& c : corners) {
    const Eigen::Vector3d pa = a * c, pb = b * c;
    shift = std::max(shift, std::hypot(fx * (pa.x() / pa.z() - pb.x() / pb.z()), fy * (pa.y() / pa.z() - pb.y() / pb.z())));
  }
  return shift;
}

namespace {

// The largest image motion between poses a and b of the panel's points (a 5 x 5 grid, corners
// included) that b shows inside the image, all of them when none is inside; and the farthest of those
// points from the principal point, as a fraction of the half diagonal.
struct VisibleShift {
  double shift_px = 0;
  double radius_fraction = 0;
};

VisibleShift max_visible_shift(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double width_m, double height_m,
                               double fx, double fy, double cx, double cy, cv::Size image) {
  constexpr int kGrid = 5;
  double visible = -1, any = 0, radius = 0, any_radius = 0;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const Eigen::Vector3d p((static_cast<double>(i) / (kGrid - 1) - 0.5) * width_m, (static_cast<double>(j) / (kGrid - 1) - 0.5) * height_m, 0);
      const Eigen::Vector3d pa = a * p, pb = b * p;
      const double ua = fx * pa.x() / pa.z() + cx, va = fy * pa.y() / pa.z() + cy;
      const double ub = fx * pb.x() / pb.z() + cx, vb = fy * pb.y() / pb.z() + cy;
      const double shift = std::hypot(ua - ub, va - vb);
      const double r = std::hypot(ub - cx, vb - cy);
      any = std::max(any, shift);
      any_radius = std::max(any_radius, r);
      if (pb.z() > 0 && ub >= 0 && vb >= 0 && ub <= image.width - 1 && vb <= image.height - 1) {
        visible = std::max(visible, shift);
        radius = std::max(radius, r);
      }
    }
  }
  const double half_diagonal = 0.5 * std::hypot(image.width, image.height);
  if (visible < 0) return {any, std::min(1.0, any_radius / half_diagonal)};
  return {visible, std::min(1.0, radius / half_diagonal)};
}

}  // namespace

bool finish_refinement(const GaussNewtonRun& run, const Eigen::Isometry3d& T_start, double leash_px, double width_m,
                       double height_m, double fx, double fy, double cx, double cy, cv::Size image,
                       const Se3RefinerSettings& settings, Se3Refinement& out) {
  out.iterations = run.iterations;
  if (*run.failure != '\0') {
    out.failure = run.failure;
    return false;
  }
  if (!(run.appearance.gain > 1e-3) || !run.T.matrix().allFinite()) {
    out.failure = "no correlation with the template";
    out.contradicts_start = true;
    return false;
  }
  // The correlation of the fitted model with the frame: the share of the grey levels' variance it explains.
  const PhotometricNormal& fit = run.normal;
  const double variance_sum = fit.sum_grey2 - fit.sum_grey * fit.sum_grey / std::max(1, fit.valid);
  out.correlation = variance_sum > 0 ? std::sqrt(std::max(0.0, 1.0 - fit.ssr / variance_sum)) : 0.0;
  if (out.correlation < settings.min_correlation) {
    out.failure = "the fit does not explain the frame (correlation below the threshold)";
    out.contradicts_start = true;
    return false;
  }
  const VisibleShift moved = max_visible_shift(run.T, T_start, width_m, height_m, fx, fy, cx, cy, image);
  if (moved.shift_px > leash_px + settings.calibration_error_px * moved.radius_fraction) {
    out.failure = "the pose moved too far from the homography's";
    out.contradicts_start = true;
    return false;
  }
  const PhotometricNormal& n = run.normal;
  const double dof = std::max(1, n.valid - kPhotometricParams);
  const double inflation = settings.covariance_inflation * settings.covariance_inflation;
  const PhotometricMatrix cov = (n.ssr / dof) * inflation * n.JtJ.ldlt().solve(PhotometricMatrix::Identity());
  out.covariance = cov.topLeftCorner<6, 6>();
  // Model errors the Gauss-Newton covariance does not see (blur and resampling differences between
  // template and frame): a floor on the rotation's standard deviation on every axis.
  out.covariance.topLeftCorner<3, 3>() +=
      Eigen::Matrix3d::Identity() * settings.rotation_sigma_floor_rad * settings.rotation_sigma_floor_rad;
  const Eigen::Vector3d& t = run.T.translation();
  Eigen::Matrix3d t_cross;  // translation of exp(xi) T: t + omega x t + v
  t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  Eigen::Matrix<double, 3, 6> J_t;
  J_t << -t_cross, Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d cov_t = J_t * out.covariance * J_t.transpose();
  const Eigen::Matrix3d cov_r = out.covariance.topLeftCorner<3, 3>();
  out.rotation_sigma_rad = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov_r).eigenvalues().maxCoeff()));
  out.position_sigma_m = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov_t).eigenvalues().maxCoeff()));
  out.residual_grey = std::sqrt(n.ssr / std::max(1, n.valid));
  out.T_cam_object = run.T;
  out.refined = true;
  return true;
}

}  // namespace labo::planar
