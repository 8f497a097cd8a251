#include "localization/estimation/scale_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace labo {

ScaleEstimator::ScaleEstimator(double sigma_map, double sigma_metric, double pair_sigma_metric, double initial_scale)
    : sigma_map_(sigma_map), sigma_metric_(sigma_metric), pair_sigma_metric_(pair_sigma_metric),
      initial_scale_(initial_scale) {
  reset(initial_scale);
}

void ScaleEstimator::reset(double initial_scale) {
  initial_scale_ = initial_scale;
  map_.clear();
  metric_.clear();
  pair_scales_.clear();
  status_ = ScaleStatus{};
  status_.scale = initial_scale;
}

double ScaleEstimator::ml_scale(double s_pp, double s_ii, double s_pi, double sigma_map, double sigma_metric) {
  // Maximizes the likelihood of m_i = lambda p_i with noise sigma_map on p, sigma_metric on m: the
  // positive root of sigma_p^2 S_PI lambda^2 - (sigma_p^2 S_II - sigma_i^2 S_PP) lambda - sigma_i^2 S_PI.
  const double sp2 = sigma_map * sigma_map, si2 = sigma_metric * sigma_metric;
  const double b = sp2 * s_ii - si2 * s_pp;
  if (std::abs(s_pi) < 1e-12) return 0.0;
  const double root = std::sqrt(b * b + 4.0 * sp2 * si2 * s_pi * s_pi);
  // The two algebraically equal forms; each avoids cancellation on its side of b = 0.
  return b >= 0 ? (b + root) / (2.0 * sp2 * s_pi) : (2.0 * si2 * s_pi) / (root - b);
}

bool ScaleEstimator::add_pair(const Eigen::Vector3d& map_displacement, const Eigen::Vector3d& metric_displacement) {
  if (!map_displacement.allFinite() || !metric_displacement.allFinite()) return false;
  if (map_displacement.norm() < 0.05 || metric_displacement.norm() < 0.05) return false;
  const double alpha = ml_scale(map_displacement.squaredNorm(), metric_displacement.squaredNorm(),
                                map_displacement.dot(metric_displacement), sigma_map_, pair_sigma_metric_);
  if (!(alpha > 0) || !std::isfinite(alpha)) return false;
  map_.push_back(map_displacement);
  metric_.push_back(metric_displacement);
  pair_scales_.push_back(alpha);
  recompute();
  return true;
}

void ScaleEstimator::recompute() {
  // Reference for outlier rejection: the median of single-pair scales once there are 5 of them.
  double reference = initial_scale_;
  if (pair_scales_.size() >= 5) {
    std::vector<double> sorted = pair_scales_;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    reference = sorted[sorted.size() / 2];
  }
  double s_pp = 0, s_ii = 0, s_pi = 0;
  int inliers = 0;
  double sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < pair_scales_.size(); ++i) {
    if (!(pair_scales_[i] > 0.2 * reference && pair_scales_[i] < 5.0 * reference)) continue;
    s_pp += map_[i].squaredNorm();
    s_ii += metric_[i].squaredNorm();
    s_pi += map_[i].dot(metric_[i]);
    sum += pair_scales_[i];
    sum2 += pair_scales_[i] * pair_scales_[i];
    ++inliers;
  }
  status_.pairs = static_cast<int>(pair_scales_.size());
  status_.inliers = inliers;
  if (inliers == 0) return;
  const double lambda = ml_scale(s_pp, s_ii, s_pi, sigma_map_, sigma_metric_);
  if (!(lambda > 0.1 * reference) || !std::isfinite(lambda)) return;
  status_.scale = lambda;
  status_.estimated = true;
  status_.accuracy = 0.5 + 0.5 * std::clamp(s_pi * lambda / 4.0, 0.0, 1.0);
  const double mean = sum / inliers;
  const double var = std::max(0.0, sum2 / inliers - mean * mean);
  status_.relative_std = inliers > 1 ? std::sqrt(var / (inliers - 1)) / mean : 1.0;
}

void MapToWorld::initialize(const Eigen::Isometry3d& T_map_cam, const Eigen::Isometry3d& T_world_cam, double scale) {
  scale_ = scale;
  R_ = T_world_cam.linear() * T_map_cam.linear().transpose();
  t_ = T_world_cam.translation() - R_ * (scale_ * T_map_cam.translation());
  fixpoint_map_ = T_map_cam.translation();
  initialized_ = true;
}

void MapToWorld::refine_rotation(const Eigen::Isometry3d& T_map_cam, const Eigen::Isometry3d& T_world_cam,
                                 double weight) {
  // Rotate about the fixpoint so its world position stays put.
  const Eigen::Vector3d fix_world = R_ * (scale_ * fixpoint_map_) + t_;
  const Eigen::Quaterniond q_old(R_);
  const Eigen::Quaterniond q_new(Eigen::Matrix3d(T_world_cam.linear() * T_map_cam.linear().transpose()));
  R_ = q_old.slerp(std::clamp(weight, 0.0, 1.0), q_new).normalized().toRotationMatrix();
  t_ = fix_world - R_ * (scale_ * fixpoint_map_);
}

void MapToWorld::set_scale(double new_scale) {
  // p_world(fix) = R (lambda fix) + t must not move: t += R (lambda_old - lambda_new) fix.
  t_ += R_ * ((scale_ - new_scale) * fixpoint_map_);
  scale_ = new_scale;
}

Eigen::Isometry3d MapToWorld::T_world_cam(const Eigen::Isometry3d& T_map_cam) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_ * T_map_cam.linear();
  T.translation() = R_ * (scale_ * T_map_cam.translation()) + t_;
  return T;
}

}  // namespace labo
