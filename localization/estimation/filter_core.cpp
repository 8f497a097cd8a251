#include "localization/estimation/filter_core.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/frames.hpp"

namespace labo::estimation {

using namespace est;

namespace {
constexpr Seconds kCommandValidity = 1.0;   // a command older than this no longer drives the model
// A navdata yaw increment larger than the drone can turn in the packet interval is a firmware reset,
// not a rotation: re-anchor instead of fusing it. tum_ardrone gates at 10 deg per packet, at 200 Hz;
// at demo navdata's 15 Hz a knock turns the drone faster than that (a 0.4 rad yaw kick turns it
// 13 deg in 33 ms, ~18 deg between packets), and a 10 deg gate would leave the estimate on the old
// yaw until vision re-synced it. So the bound is a rate, two turns per second, and never below 10 deg
// nor above 90 deg (after a long navdata gap). Test "estimation: demo navdata's yaw follows a knock
// turning faster than 10 deg a packet, and a reset is not followed".
constexpr double kYawJumpMinRad = 10.0 * std::numbers::pi / 180.0;
constexpr double kYawJumpMaxRad = 90.0 * std::numbers::pi / 180.0;
constexpr double kMaxYawRateRadps = 4.0 * std::numbers::pi;
constexpr double kMinRange = 0.05, kMaxRange = 6.0;

template <int M>
Eigen::Matrix<double, M, M> diag_sq(const Eigen::Matrix<double, M, 1>& sigma) {
  return sigma.cwiseProduct(sigma).asDiagonal();
}
}  // namespace

FilterCore::FilterCore(const EstimatorConfig& config, double gamma_m)
    : config_(config), ekf_(config.model, config.noise),
      altitude_(gamma_m, config.altitude_step_discrimination ? AltitudeTracker::Mode::Discriminating
                                                              : AltitudeTracker::Mode::PaperGammaOnly),
      dropout_(config.velocity_dropout, config.model, config.firmware_command_hold_s) {}

void FilterCore::reset(const StateVector& s, const StateCovariance& P, Seconds t) {
  ekf_.reset(s, P);
  t_ = t;
  initialized_ = true;
  command_.reset();
  yaw_anchored_ = false;
  last_nav_valid_ = false;
  altitude_.reset();
  dropout_.reset();
  ekf_.reset_xy_accel_noise();
  odometry_ = {};
  counters_ = {};
  drift_bound_m_ = 0;
}

void FilterCore::predict_to(Seconds t) {
  if (!(t > t_)) return;
  const bool command_valid = command_ && t_ >= command_effect_t_ && t_ - command_effect_t_ <= kCommandValidity;
  ekf_.predict(t - t_, command_valid ? command_ : std::nullopt);
  t_ = t;
}

void FilterCore::hover_to(Seconds t, double stop_time_s) {
  if (!(t > t_)) return;
  ekf_.predict_firmware_hover(t - t_, stop_time_s);
  t_ = t;
  set_command(MoveCommand{}, t);
}

void FilterCore::set_command(const MoveCommand& command, Seconds effect_time) {
  command_ = command;
  command_effect_t_ = effect_time;
}

void FilterCore::apply_navdata(const NavdataSample& n, bool vision_holding, const SurfaceMap* map) {
  const Seconds gap = last_nav_valid_ ? t_ - last_nav_t_ : 0.0;
  observe_attitude(n);
  observe_yaw(n, vision_holding, gap);
  if (n.control_state == control_state::kLanded) {
    // On the ground: the next take-off starts with a flat trim (the missions' executors send one), so
    // the tilt offset is learned anew in each flight.
    dropout_.reset();
    ekf_.set_tilt_bias_accel(Eigen::Vector2d::Zero());
    ekf_.reset_xy_accel_noise();
    observe_landed();
  } else {
    observe_velocity(n, vision_holding);
    observe_altitude(n, map);
  }
  // Odometry for the scale pairs: body velocities rotated by the filter's yaw, integrated. A velocity
  // dropout leaves it without coverage, like a navdata gap (the pair is not used).
  const double yaw = ekf_.state()(YAW);
  const Eigen::Vector2d v_world(std::cos(yaw) * n.vx_mps - std::sin(yaw) * n.vy_mps,
                                std::sin(yaw) * n.vx_mps + std::cos(yaw) * n.vy_mps);
  if (!vision_holding && n.control_state != control_state::kLanded) {
    const DriftBoundSettings& d = config_.drift_bound;
    const double dropout = dropout_.in_dropout() ? d.dropout_mps : 0.0;
    drift_bound_m_ += gap * (d.velocity_bias_mps + d.velocity_scale * v_world.norm() + dropout);
  }
  if (dropout_.in_dropout()) {
    odometry_.max_gap = std::max(odometry_.max_gap, t_ - dropout_.dropout_start() + gap);
  } else {
    odometry_.xy += v_world * gap;
    odometry_.max_gap = std::max(odometry_.max_gap, gap);
  }
  last_nav_valid_ = true;
  last_nav_t_ = t_;
}

void FilterCore::observe_attitude(const NavdataSample& n) {
  Eigen::Matrix<double, 2, N> H = Eigen::Matrix<double, 2, N>::Zero();
  H(0, ROLL) = H(1, PITCH) = 1.0;
  const Eigen::Vector2d y(n.roll_rad - ekf_.state()(ROLL), n.pitch_rad - ekf_.state()(PITCH));
  const double s = config_.noise.attitude_obs_rad;
  ekf_.update<2>(y, H, Eigen::Vector2d(s * s, s * s).asDiagonal());
}

void FilterCore::observe_yaw(const NavdataSample& n, bool vision_holding, Seconds gap) {
  // Only increments of the navdata yaw are trusted (its absolute value drifts and starts anywhere).
  // Without vision the anchor is kept, so the filter follows the IMU's yaw; with vision it moves every
  // packet, so the IMU only constrains the change between packets (tum_ardrone's two modes).
  const double jump_rad = std::clamp(kMaxYawRateRadps * gap, kYawJumpMinRad, kYawJumpMaxRad);
  const bool jump = yaw_anchored_ && std::abs(wrap_angle(n.yaw_rad - last_navdata_yaw_)) > jump_rad;
  if (yaw_anchored_ && !jump) {
    Eigen::Matrix<double, 1, N> H = Eigen::Matrix<double, 1, N>::Zero();
    H(0, YAW) = 1.0;
    const double z = yaw_anchor_filter_ + wrap_angle(n.yaw_rad - yaw_anchor_navdata_);
    Eigen::Matrix<double, 1, 1> y(wrap_angle(z - ekf_.state()(YAW)));
    Eigen::Matrix<double, 1, 1> R(config_.noise.yaw_increment_rad * config_.noise.yaw_increment_rad);
    ekf_.update<1>(y, H, R);
  }
  if (!yaw_anchored_ || jump || vision_holding) {
    yaw_anchor_filter_ = ekf_.state()(YAW);
    yaw_anchor_navdata_ = n.yaw_rad;
    yaw_anchored_ = true;
  }
  last_navdata_yaw_ = n.yaw_rad;
}

bool FilterCore::velocity_usable(const NavdataSample& n) {
  if (!config_.velocity_dropout.enabled) return true;
  const StateVector& s = ekf_.state();
  const double c = std::cos(s(YAW)), sn = std::sin(s(YAW));
  const Eigen::Vector2d measured_world(c * n.vx_mps - sn * n.vy_mps, sn * n.vx_mps + c * n.vy_mps);
  const VelocityVerdict v = dropout_.process(t_, measured_world, ekf_.thrust_accel(n.roll_rad, n.pitch_rad, s(YAW)),
                                             s(YAW), s.segment<2>(VX));
  ekf_.set_tilt_bias_accel(dropout_.tilt_bias_accel());
  if (v.onset) {
    const DropoutCorrection& k = dropout_.correction();
    ekf_.mutable_state().segment<2>(VX) += k.velocity;
    ekf_.mutable_state().segment<2>(X) += k.position;
    for (int i = 0; i < 2; ++i) {
      ekf_.add_variance(VX + i, k.velocity(i) * k.velocity(i));
      ekf_.add_variance(X + i, k.position(i) * k.position(i));
    }
    ekf_.set_xy_accel_noise(dropout_.settings().dropout_accel_noise_mps2);
    ++counters_.velocity_dropouts;
  }
  if (!dropout_.in_dropout()) ekf_.reset_xy_accel_noise();  // resumed, or started again after a gap
  if (!v.fuse) ++counters_.velocity_dropout_packets;
  return v.fuse;
}

void FilterCore::observe_velocity(const NavdataSample& n, bool vision_holding) {
  const bool usable = velocity_usable(n);
  if (usable) fuse_horizontal_velocity(n, vision_holding);
  dropout_.record_filter_velocity(ekf_.state().segment<2>(VX));
  if (config_.use_navdata_vz) {
    Eigen::Matrix<double, 1, N> Hz = Eigen::Matrix<double, 1, N>::Zero();
    Hz(0, VZ) = 1.0;
    Eigen::Matrix<double, 1, 1> y(n.vz_mps - ekf_.state()(VZ));
    Eigen::Matrix<double, 1, 1> R(config_.noise.vertical_velocity_mps * config_.noise.vertical_velocity_mps);
    ekf_.update<1>(y, Hz, R);
  }
}

void FilterCore::fuse_horizontal_velocity(const NavdataSample& n, bool vision_holding) {
  // Body-frame velocities h(s) = Rz(yaw)^T (vx, vy), with their yaw Jacobian.
  const StateVector& s = ekf_.state();
  const double c = std::cos(s(YAW)), sn = std::sin(s(YAW));
  const Eigen::Vector2d predicted(c * s(VX) + sn * s(VY), -sn * s(VX) + c * s(VY));
  Eigen::Matrix<double, 2, N> H = Eigen::Matrix<double, 2, N>::Zero();
  H(0, VX) = c;
  H(0, VY) = sn;
  H(0, YAW) = -sn * s(VX) + c * s(VY);
  H(1, VX) = -sn;
  H(1, VY) = c;
  H(1, YAW) = -c * s(VX) - sn * s(VY);
  const double sigma = vision_holding ? config_.noise.velocity_with_vision_mps : config_.noise.velocity_mps;
  ekf_.update<2>(Eigen::Vector2d(n.vx_mps, n.vy_mps) - predicted, H, diag_sq<2>(Eigen::Vector2d(sigma, sigma)));
}

void FilterCore::observe_altitude(const NavdataSample& n, const SurfaceMap* map) {
  if (!(n.altitude_m >= kMinRange && n.altitude_m <= kMaxRange)) return;
  const StateVector& s = ekf_.state();
  // The sonar looks along the body's -z: its range times cos(roll) cos(pitch) is the vertical distance.
  const double range = n.altitude_m * std::cos(s(ROLL)) * std::cos(s(PITCH));
  const double xy_sigma = std::sqrt(std::max(ekf_.covariance()(X, X), ekf_.covariance()(Y, Y)));
  const AltitudeDecision d = altitude_.process(range, t_, s(Z), n.vz_mps, s.segment<2>(X), xy_sigma, map);
  if (d.kind == AltitudeDecision::Kind::FloorStep) {
    ++counters_.floor_steps;
    ++odometry_.floor_steps;
  }
  if (d.kind == AltitudeDecision::Kind::FusedAsMotion) ++counters_.fused_as_motion;
  if (d.kind == AltitudeDecision::Kind::ShortEcho) ++counters_.short_echoes;
  if (d.fuse()) {
    Eigen::Matrix<double, 1, N> H = Eigen::Matrix<double, 1, N>::Zero();
    H(0, Z) = 1.0;
    Eigen::Matrix<double, 1, 1> y(d.z_observed - ekf_.state()(Z));
    Eigen::Matrix<double, 1, 1> R(config_.noise.ultrasound_m * config_.noise.ultrasound_m);
    ekf_.update<1>(y, H, R);
    odometry_.z += d.range_increment;
  }
  altitude_.set_reference_z(ekf_.state()(Z));
}

void FilterCore::observe_landed() {
  // On the ground: no motion (the sonar reads nothing useful that close).
  Eigen::Matrix<double, 3, N> H = Eigen::Matrix<double, 3, N>::Zero();
  H(0, VX) = H(1, VY) = H(2, VZ) = 1.0;
  const Eigen::Vector3d y = -ekf_.state().segment<3>(VX);
  ekf_.update<3>(y, H, Eigen::Vector3d::Constant(0.01 * 0.01).asDiagonal());
}

}  // namespace labo::estimation
