#include "localization/estimation/scale_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace labo::estimation {

namespace {
// Pairs older than this many memories weigh less than 2 % and are dropped.
constexpr double kKeptMemories = 4.0;

std::size_t kept_pairs(double memory_pairs) { return static_cast<std::size_t>(std::ceil(kKeptMemories * memory_pairs)); }
}  // namespace

ScaleEstimator::ScaleEstimator(const ScaleSettings& settings) : settings_(settings) {
  const std::size_t n = kept_pairs(settings_.memory_pairs) + 1;
  pairs_.reserve(n);
  weights_.reserve(n);
  sorted_.reserve(n);
  reset(settings.initial_scale);
}

void ScaleEstimator::reset(double initial_scale) {
  settings_.initial_scale = initial_scale;
  pairs_.clear();
  outliers_at_arrival_ = 0;
  scale_changes_ = 0;
  was_estimated_ = false;
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
  if (metric_displacement.norm() < settings_.min_displacement_m || map_displacement.norm() < 1e-9) return false;
  if (!(map_displacement.dot(metric_displacement) > 0)) return false;  // a negative scale is no scale
  const Pair pair{map_displacement, metric_displacement, metric_displacement.norm() / map_displacement.norm()};
  const bool refused = status_.estimated && !inlier(pair, status_.scale);
  outliers_at_arrival_ += refused ? 1 : 0;
  if (pairs_.size() >= kept_pairs(settings_.memory_pairs)) pairs_.erase(pairs_.begin());
  pairs_.push_back(pair);
  if (status_.estimated) {
    if (const int k = changed_pairs(); k > 0) {
      // The map's scale changed: what came before describes another map.
      pairs_.erase(pairs_.begin(), pairs_.end() - k);
      ++scale_changes_;
    }
  }
  recompute();
  return true;
}

int ScaleEstimator::changed_pairs() const {
  // The newest k pairs' own scale against the current estimate, each with its least-squares variance
  // (residual variance / sum of |q|^2): a change is declared when they differ by more than 3 sigma
  // and every one of the k pairs agrees with their own scale. Small pairs (0.2 m, ~15 % noise each)
  // cannot show a 20-40 % change alone; a few together can.
  const double var_r = settings_.sigma_metric_m * settings_.sigma_metric_m + settings_.sigma_map_m * settings_.sigma_map_m;
  const int n = static_cast<int>(pairs_.size());
  double old_qq = 0;
  for (int i = 0; i < n; ++i) old_qq += inlier(pairs_[i], status_.scale) ? pairs_[i].map.squaredNorm() : 0.0;
  double new_qq = 0, new_qm = 0;
  for (int k = 1; k <= std::min(kChangeMaxPairs, n - 1); ++k) {
    const Pair& p = pairs_[n - k];
    new_qq += p.map.squaredNorm();
    new_qm += p.map.dot(p.metric);
    if (inlier(p, status_.scale)) old_qq -= p.map.squaredNorm();
    if (k < kChangeMinPairs || old_qq <= 0) continue;
    const double lambda_new = new_qm / new_qq;
    const double sigma = std::sqrt(var_r / new_qq + var_r / old_qq);
    if (std::abs(lambda_new - status_.scale) <= 3.0 * sigma) continue;
    bool agree = true;
    for (int j = n - k; j < n; ++j) agree = agree && inlier(pairs_[j], lambda_new);
    if (agree) return k;
  }
  return 0;
}

double ScaleEstimator::weighted_median_scale() {
  sorted_.clear();
  double total = 0;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    sorted_.emplace_back(pairs_[i].alpha, weights_[i]);
    total += weights_[i];
  }
  if (sorted_.empty()) return 0.0;  // no pair: no reference, and nothing to gate
  std::sort(sorted_.begin(), sorted_.end());
  double below = 0;
  for (const auto& [alpha, w] : sorted_) {
    below += w;
    if (below >= 0.5 * total) return alpha;
  }
  return sorted_.back().first;
}

bool ScaleEstimator::inlier(const Pair& p, double reference) const {
  const double var = settings_.sigma_metric_m * settings_.sigma_metric_m + settings_.sigma_map_m * settings_.sigma_map_m;
  return (p.metric - reference * p.map).squaredNorm() / var <= settings_.outlier_chi2;
}

void ScaleEstimator::recompute() {
  const double forget = 1.0 - 1.0 / settings_.memory_pairs;
  weights_.clear();
  for (std::size_t i = 0; i < pairs_.size(); ++i) weights_.push_back(std::pow(forget, double(pairs_.size() - 1 - i)));
  status_.pairs = static_cast<int>(pairs_.size());
  // Too few pairs for a median to mean anything: all are taken.
  const bool gate = pairs_.size() >= static_cast<std::size_t>(kMinInliers);
  const double ref = weighted_median_scale();
  double s_pp = 0, s_ii = 0, s_pi = 0, w_sum = 0, sum = 0, sum2 = 0;
  int inliers = 0;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const Pair& p = pairs_[i];
    if (gate && !inlier(p, ref)) continue;
    const double w = weights_[i];
    s_pp += w * p.map.squaredNorm();
    s_ii += w * p.metric.squaredNorm();
    s_pi += w * p.map.dot(p.metric);
    w_sum += w;
    sum += w * p.alpha;
    sum2 += w * p.alpha * p.alpha;
    ++inliers;
  }
  status_.inliers = inliers;
  if (inliers == 0) return;
  // The map's noise in map units at the reference scale: both sides weigh as metres.
  const double lambda = ml_scale(s_pp, s_ii, s_pi, settings_.sigma_map_m / ref, settings_.sigma_metric_m);
  if (!(lambda > 0.1 * ref) || !std::isfinite(lambda)) return;
  status_.scale = lambda;
  was_estimated_ = was_estimated_ || inliers >= kMinInliers;
  status_.estimated = was_estimated_;
  status_.accuracy = 0.5 + 0.5 * std::clamp(s_pi * lambda / 4.0, 0.0, 1.0);
  const double mean = sum / w_sum;
  const double var = std::max(0.0, sum2 / w_sum - mean * mean);
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

}  // namespace labo::estimation
