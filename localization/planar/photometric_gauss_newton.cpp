#include "localization/planar/photometric_gauss_newton.hpp"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace labo {

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

bool finish_refinement(const GaussNewtonRun& run, const Eigen::Isometry3d& T_start, double leash_px, double width_m,
                       double height_m, double fx, double fy, const Se3RefinerSettings& settings, Se3Refinement& out) {
  out.iterations = run.iterations;
  if (*run.failure != '\0') {
    out.failure = run.failure;
    return false;
  }
  if (!(run.appearance.gain > 1e-3) || !run.T.matrix().allFinite()) {
    out.failure = "no correlation with the template";
    return false;
  }
  if (max_corner_shift_px(run.T, T_start, width_m, height_m, fx, fy) > leash_px) {
    out.failure = "the pose moved too far from the homography's";
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

}  // namespace labo
