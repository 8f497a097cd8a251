#include "localization/planar/pose/planar_pose_filter.hpp"

#include <cmath>

namespace labo::planar {

namespace {
// A measurement without a usable sigma restarts the filter as barely informative.
constexpr double kUnknownSigmaRad = 0.1;

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}
}  // namespace

PlanarPoseFilter::PlanarPoseFilter(PlanarPoseFilterSettings settings) : settings_(settings) {}

FilteredOrientation PlanarPoseFilter::restart(const Eigen::Matrix3d& R, double variance, Seconds t) {
  State s;
  s.R = R;
  s.t = t;
  const double rate_var = settings_.initial_rate_sigma_radps * settings_.initial_rate_sigma_radps;
  s.P << variance, 0, 0, rate_var;
  state_ = s;
  FilteredOrientation out;
  out.R_cam_object = R;
  out.rotation_sigma_rad = std::sqrt(variance);
  out.restarted = true;
  return out;
}

FilteredOrientation PlanarPoseFilter::update(const Eigen::Matrix3d& R_cam_object, double rotation_sigma_rad, Seconds t) {
  const double r = rotation_sigma_rad * rotation_sigma_rad;
  if (!(rotation_sigma_rad > 0) || !std::isfinite(r)) return restart(R_cam_object, kUnknownSigmaRad * kUnknownSigmaRad, t);
  if (!state_ || !(t > state_->t) || t - state_->t > settings_.max_gap_s) return restart(R_cam_object, r, t);
  State& s = *state_;
  // Predict: constant angular velocity; white angular acceleration.
  const double dt = t - s.t;
  s.R = exp_so3(s.rate * dt) * s.R;
  Eigen::Matrix2d F;
  F << 1, dt, 0, 1;
  const double q = settings_.angular_accel_radps2 * settings_.angular_accel_radps2;
  Eigen::Matrix2d Q;
  Q << q * dt * dt * dt / 3, q * dt * dt / 2, q * dt * dt / 2, q * dt;
  s.P = F * s.P * F.transpose() + Q;
  s.t = t;
  // Update on the tangent space at the prediction.
  const Eigen::Vector3d innovation = log_so3(R_cam_object * s.R.transpose());
  const double S = s.P(0, 0) + r;
  FilteredOrientation out;
  if (innovation.squaredNorm() / S > settings_.gate_chi2) {
    if (++s.skipped >= settings_.max_skipped) return restart(R_cam_object, r, t);
    out.R_cam_object = s.R;
    out.rotation_sigma_rad = std::sqrt(s.P(0, 0));
    out.skipped = true;
    return out;
  }
  s.skipped = 0;
  const Eigen::Vector2d K = s.P.col(0) / S;
  s.R = exp_so3(K(0) * innovation) * s.R;
  s.rate += K(1) * innovation;
  s.P = (Eigen::Matrix2d::Identity() - K * Eigen::RowVector2d(1, 0)) * s.P;
  out.R_cam_object = s.R;
  out.rotation_sigma_rad = std::sqrt(s.P(0, 0));
  return out;
}

}  // namespace labo::planar
