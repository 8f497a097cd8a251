#pragma once
// DroneEkf: the extended Kalman filter core of the StateEstimator: the 10-state vector, its
// covariance, the AR.Drone motion model (MotionModelConstants) and a generic measurement update in
// Joseph form that keeps the covariance symmetric positive definite (repairs are counted).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <optional>

#include "drone/drone_link.hpp"
#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo::estimation {

class DroneEkf {
 public:
  DroneEkf(const MotionModelConstants& model, const EstimatorNoise& noise)
      : model_(model), noise_(noise), xy_accel_noise_(noise.accel_xy_mps2) {}

  void reset(const StateVector& s, const StateCovariance& P) {
    s_ = s;
    P_ = P;
    tilt_bias_.setZero();
  }
  void set_model(const MotionModelConstants& model) { model_ = model; }

  // Propagates by dt seconds (split in steps of at most 10 ms). Without a command the attitude, yaw
  // rate and vertical speed are held (random walk); the horizontal dynamics always follow the tilt.
  void predict(double dt, const std::optional<MoveCommand>& command);
  // Propagates by dt seconds under the firmware's own hover, which holds the drone still on its
  // velocity estimate: the horizontal velocity decays with `stop_time_s`, the attitude levels, the
  // vertical speed and yaw rate die away as under a hover command.
  void predict_firmware_hover(double dt, double stop_time_s);

  // The horizontal acceleration the thrust gives at this attitude (world frame, no drag).
  Eigen::Vector2d thrust_accel(double roll, double pitch, double yaw) const;
  // The horizontal process noise (white acceleration, m/s^2/sqrt(Hz)); `reset_xy_accel_noise` restores
  // the configured one. The filter runs on the model alone during a velocity dropout.
  void set_xy_accel_noise(double sigma_mps2) { xy_accel_noise_ = sigma_mps2; }
  void reset_xy_accel_noise() { xy_accel_noise_ = noise_.accel_xy_mps2; }
  // The tilt bias: the horizontal acceleration (heading frame: x forward, y left) that the thrust
  // along the measured roll/pitch overstates (the IMU's offset, learned by VelocityDropoutDetector).
  void set_tilt_bias_accel(const Eigen::Vector2d& heading) { tilt_bias_ = heading; }
  // Adds `variance` to the diagonal element i (an estimate that was just moved by a correction).
  void add_variance(int i, double variance) {
    P_(i, i) += variance;
    keep_positive_definite();
  }

  // The continuous-time derivative of the state under a command (exposed for the model fit).
  StateVector derivative(const StateVector& s, const std::optional<MoveCommand>& command) const;

  // Measurement update with innovation y = z - h(s), Jacobian H and noise covariance R. Returns the
  // squared Mahalanobis distance of the innovation. The caller wraps angle innovations.
  template <int M>
  double update(const Eigen::Matrix<double, M, 1>& y, const Eigen::Matrix<double, M, est::N>& H,
                const Eigen::Matrix<double, M, M>& R) {
    const Eigen::Matrix<double, M, M> S = H * P_ * H.transpose() + R;
    const Eigen::LDLT<Eigen::Matrix<double, M, M>> ldlt(S);
    if (ldlt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
    const Eigen::Matrix<double, est::N, M> K = ldlt.solve(H * P_).transpose();
    s_ += K * y;
    const StateCovariance IKH = StateCovariance::Identity() - K * H;
    P_ = IKH * P_ * IKH.transpose() + K * R * K.transpose();
    keep_positive_definite();
    s_(est::YAW) = wrap(s_(est::YAW));
    return y.dot(ldlt.solve(y));
  }
  template <int M>
  double mahalanobis(const Eigen::Matrix<double, M, 1>& y, const Eigen::Matrix<double, M, est::N>& H,
                     const Eigen::Matrix<double, M, M>& R) const {
    const Eigen::Matrix<double, M, M> S = H * P_ * H.transpose() + R;
    return y.dot(S.ldlt().solve(y));
  }

  const StateVector& state() const { return s_; }
  StateVector& mutable_state() { return s_; }
  const StateCovariance& covariance() const { return P_; }
  int repairs() const { return repairs_; }

  static double wrap(double a);

 private:
  // One step; `hover_stop_s` > 0: the horizontal velocity decays with it instead of following the tilt.
  void step(double dt, const std::optional<MoveCommand>& command, double hover_stop_s = 0.0);
  void keep_positive_definite();

  MotionModelConstants model_;
  EstimatorNoise noise_;
  double xy_accel_noise_;
  Eigen::Vector2d tilt_bias_ = Eigen::Vector2d::Zero();
  StateVector s_ = StateVector::Zero();
  StateCovariance P_ = StateCovariance::Identity();
  int repairs_ = 0;
};

}  // namespace labo::estimation
