#include "localization/estimation/drone_ekf.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::estimation {

using namespace est;

namespace {
// Clip a normalized command to [-1, 1]; a non-finite value counts as 0 (the link hovers on it).
double clip_unit(double u) { return std::isfinite(u) ? std::clamp(u, -1.0, 1.0) : 0.0; }

// Horizontal part of the body z axis in the world, for roll, pitch, yaw (Rz(yaw) Ry(pitch) Rx(roll) e_z).
Eigen::Vector2d thrust_direction(double roll, double pitch, double yaw) {
  const double fbx = std::cos(roll) * std::sin(pitch);
  const double fby = -std::sin(roll);
  return {std::cos(yaw) * fbx - std::sin(yaw) * fby, std::sin(yaw) * fbx + std::cos(yaw) * fby};
}
}  // namespace

double DroneEkf::wrap(double a) { return wrap_angle(a); }

Eigen::Vector2d DroneEkf::thrust_accel(double roll, double pitch, double yaw) const {
  return model_.thrust_accel_mps2 * thrust_direction(roll, pitch, yaw);
}

StateVector DroneEkf::derivative(const StateVector& s, const std::optional<MoveCommand>& command) const {
  StateVector d = StateVector::Zero();
  d(X) = s(VX);
  d(Y) = s(VY);
  d(Z) = s(VZ);
  const Eigen::Vector2d f = thrust_direction(s(ROLL), s(PITCH), s(YAW));
  const double cy = std::cos(s(YAW)), sy = std::sin(s(YAW));
  d(VX) = model_.thrust_accel_mps2 * f.x() - (cy * tilt_bias_.x() - sy * tilt_bias_.y()) - model_.drag_per_s * s(VX);
  d(VY) = model_.thrust_accel_mps2 * f.y() - (sy * tilt_bias_.x() + cy * tilt_bias_.y()) - model_.drag_per_s * s(VY);
  d(YAW) = s(YAW_RATE);
  if (command) {
    d(ROLL) = model_.attitude_rate_hz * (model_.tilt_max_rad * clip_unit(command->roll) - s(ROLL));
    d(PITCH) = model_.attitude_rate_hz * (model_.tilt_max_rad * clip_unit(command->pitch) - s(PITCH));
    d(YAW_RATE) = model_.yaw_response_hz * (model_.yaw_rate_max_radps * clip_unit(command->yaw_rate) - s(YAW_RATE));
    d(VZ) = model_.vertical_response_hz * (model_.vz_max_mps * clip_unit(command->gaz) - s(VZ));
  }
  return d;
}

void DroneEkf::predict(double dt, const std::optional<MoveCommand>& command) {
  if (!(dt > 0)) return;
  constexpr double max_step = 0.01;
  const int steps = static_cast<int>(std::ceil(dt / max_step));
  const double h = dt / steps;
  for (int i = 0; i < steps; ++i) step(h, command);
}

void DroneEkf::predict_firmware_hover(double dt, double stop_time_s) {
  if (!(dt > 0) || !(stop_time_s > 0)) return;
  constexpr double max_step = 0.01;
  const int steps = static_cast<int>(std::ceil(dt / max_step));
  const double h = dt / steps;
  for (int i = 0; i < steps; ++i) step(h, MoveCommand{}, stop_time_s);
}

void DroneEkf::step(double dt, const std::optional<MoveCommand>& command, double hover_stop_s) {
  // Jacobian of the derivative (continuous time), then F = I + A dt.
  StateCovariance A = StateCovariance::Zero();
  A(X, VX) = A(Y, VY) = A(Z, VZ) = 1.0;
  A(YAW, YAW_RATE) = 1.0;
  const double g = model_.thrust_accel_mps2;
  const double r = s_(ROLL), p = s_(PITCH), y = s_(YAW);
  const double fbx = std::cos(r) * std::sin(p), fby = -std::sin(r);
  const double dfbx_dr = -std::sin(r) * std::sin(p), dfbx_dp = std::cos(r) * std::cos(p);
  const double dfby_dr = -std::cos(r);
  const double cy = std::cos(y), sy = std::sin(y);
  A(VX, ROLL) = g * (cy * dfbx_dr - sy * dfby_dr);
  A(VX, PITCH) = g * (cy * dfbx_dp);
  A(VX, YAW) = g * (-sy * fbx - cy * fby) + (sy * tilt_bias_.x() + cy * tilt_bias_.y());
  A(VY, ROLL) = g * (sy * dfbx_dr + cy * dfby_dr);
  A(VY, PITCH) = g * (sy * dfbx_dp);
  A(VY, YAW) = g * (cy * fbx - sy * fby) - (cy * tilt_bias_.x() - sy * tilt_bias_.y());
  A(VX, VX) = A(VY, VY) = -model_.drag_per_s;
  if (hover_stop_s > 0) {
    A.block<2, 1>(VX, ROLL).setZero();
    A.block<2, 1>(VX, PITCH).setZero();
    A.block<2, 1>(VX, YAW).setZero();
    A(VX, VX) = A(VY, VY) = -1.0 / hover_stop_s;
  }
  if (command) {
    A(ROLL, ROLL) = A(PITCH, PITCH) = -model_.attitude_rate_hz;
    A(YAW_RATE, YAW_RATE) = -model_.yaw_response_hz;
    A(VZ, VZ) = -model_.vertical_response_hz;
  }

  // State: velocities first (semi-implicit), positions with the mean velocity.
  StateVector d = derivative(s_, command);
  if (hover_stop_s > 0) d.segment<2>(VX) = -s_.segment<2>(VX) / hover_stop_s;
  const Eigen::Vector3d v_old = s_.segment<3>(VX);
  s_ += d * dt;
  s_.segment<3>(X) = s_.segment<3>(X) - d.segment<3>(X) * dt + 0.5 * (v_old + s_.segment<3>(VX)) * dt;
  s_(YAW) = wrap(s_(YAW));

  const StateCovariance F = StateCovariance::Identity() + A * dt;
  StateCovariance Q = StateCovariance::Zero();
  const auto white_accel = [&](int pos, int vel, double sigma) {
    const double q = sigma * sigma;
    Q(pos, pos) += q * dt * dt * dt / 3.0;
    Q(pos, vel) += q * dt * dt / 2.0;
    Q(vel, pos) += q * dt * dt / 2.0;
    Q(vel, vel) += q * dt;
  };
  white_accel(X, VX, xy_accel_noise_);
  white_accel(Y, VY, xy_accel_noise_);
  white_accel(Z, VZ, noise_.accel_z_mps2);
  white_accel(YAW, YAW_RATE, noise_.yaw_accel_radps2);
  Q(ROLL, ROLL) += noise_.attitude_radps * noise_.attitude_radps * dt;
  Q(PITCH, PITCH) += noise_.attitude_radps * noise_.attitude_radps * dt;
  P_ = F * P_ * F.transpose() + Q;
  keep_positive_definite();
}

void DroneEkf::keep_positive_definite() {
  P_ = 0.5 * (P_ + P_.transpose());
  const Eigen::LLT<StateCovariance> llt(P_);
  if (llt.info() == Eigen::Success && P_.diagonal().minCoeff() > 0) return;
  // Rounding pushed an eigenvalue to or below zero: clamp the spectrum and count the repair.
  const Eigen::SelfAdjointEigenSolver<StateCovariance> eig(P_);
  const StateVector lambda = eig.eigenvalues().cwiseMax(1e-12);
  P_ = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
  P_ = 0.5 * (P_ + P_.transpose());
  ++repairs_;
}

}  // namespace labo::estimation
