#include "bench/estimation/surrogate_plant.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
constexpr double kG = 9.81;
constexpr double kTiltMax = 0.21;        // rad at full command (euler_angle_max 12 deg)
constexpr double kAttitudeOmega = 11.0;  // rad/s, second-order attitude loop
constexpr double kAttitudeZeta = 0.75;
constexpr double kYawRateMax = 1.7;      // rad/s
constexpr double kYawResponse = 6.0;     // 1/s
constexpr double kVzMax = 0.8;           // m/s
constexpr double kVzResponse = 4.0;      // 1/s
constexpr double kVzLag = 12.0;          // 1/s, motor lag before the vertical loop
constexpr double kLinearDrag = 0.35;     // 1/s
constexpr double kQuadraticDrag = 0.12;  // 1/m
double clip(double u) { return std::isfinite(u) ? std::clamp(u, -1.0, 1.0) : 0.0; }
}  // namespace

SurrogatePlant::SurrogatePlant(unsigned seed, const SurrogatePlantOptions& options)
    : options_(options), rng_(seed), p_(options.start) {
  // A bench under the instrument of the experiments, and the landing platform at the base.
  surfaces_.add(estimation::SurfaceRect{Eigen::Vector2d(2.6, -1.0), Eigen::Vector2d(3.4, 1.0), 0.8});
  surfaces_.add(estimation::SurfaceRect{Eigen::Vector2d(-0.3, -0.3), Eigen::Vector2d(0.3, 0.3), 0.05});
  std::uniform_real_distribution<double> drift(-1.0, 1.0);
  yaw_drift_ = drift(rng_) * 0.5 * M_PI / 180.0 / 60.0;  // up to 0.5 deg/min
}

void SurrogatePlant::move(const MoveCommand& command) {
  commands_in_flight_.emplace_back(t_ + options_.command_delay, command);
}

void SurrogatePlant::integrate(double dt) {
  std::normal_distribution<double> n(0.0, 1.0);
  // Attitude: second-order loops toward the commanded angles.
  const auto attitude = [&](double& angle, double& rate, double target) {
    const double acc = kAttitudeOmega * kAttitudeOmega * (target - angle) - 2.0 * kAttitudeZeta * kAttitudeOmega * rate;
    rate += acc * dt;
    angle += rate * dt;
  };
  attitude(roll_, roll_rate_, kTiltMax * clip(active_.roll));
  attitude(pitch_, pitch_rate_, kTiltMax * clip(active_.pitch));
  yaw_rate_ += kYawResponse * (kYawRateMax * clip(active_.yaw_rate) - yaw_rate_) * dt;
  yaw_ = wrap_angle(yaw_ + yaw_rate_ * dt);
  // Vertical: a lagged vertical-speed loop.
  vz_cmd_lag_ += kVzLag * (kVzMax * clip(active_.gaz) - vz_cmd_lag_) * dt;
  const double az = kVzResponse * (vz_cmd_lag_ - v_.z());
  // Horizontal: thrust tilted by the attitude (holding altitude), drag, gusts.
  const Eigen::Vector3d thrust_dir = rotation_from_ypr(yaw_, pitch_, roll_) * Eigen::Vector3d::UnitZ();
  const double sq = std::sqrt(dt);
  gust_ += -0.5 * gust_ * dt + options_.gust_accel_mps2 * sq * Eigen::Vector2d(n(rng_), n(rng_));
  const Eigen::Vector2d vh = v_.head<2>();
  const Eigen::Vector2d ah = kG * thrust_dir.head<2>() / std::max(0.5, thrust_dir.z()) - kLinearDrag * vh -
                             kQuadraticDrag * vh.norm() * vh + gust_;
  v_.head<2>() += ah * dt;
  v_.z() += az * dt;
  p_ += v_ * dt;
  p_.z() = std::max(p_.z(), surfaces_.height_at(p_.head<2>()) + 0.05);
}

NavdataSample SurrogatePlant::sense() {
  std::normal_distribution<double> n(0.0, 1.0);
  NavdataSample s;
  s.control_state = 3;
  s.battery_percent = 80;
  s.roll_rad = roll_ + 0.0035 * n(rng_);
  s.pitch_rad = pitch_ + 0.0035 * n(rng_);
  s.yaw_rad = wrap_angle(yaw_ + 0.7 + yaw_drift_ * t_ + 0.002 * n(rng_));  // IMU yaw: own origin, drifting
  const Eigen::Matrix3d R = rotation_from_ypr(yaw_, pitch_, roll_);
  const Eigen::Vector3d v_body_level = rotation_from_ypr(yaw_, 0, 0).transpose() * v_;
  const double k = 1.0 + options_.velocity_scale_error;
  s.vx_mps = k * v_body_level.x() + 0.04 * n(rng_);
  s.vy_mps = k * v_body_level.y() + 0.04 * n(rng_);
  s.vz_mps = v_.z() + 0.05 * n(rng_);
  const double height = p_.z() - surfaces_.height_at(p_.head<2>());
  s.altitude_m = std::max(0.0, height / std::max(0.5, R(2, 2)) + 0.01 * n(rng_));
  return s;
}

void SurrogatePlant::step(Seconds dt, std::vector<NavdataSample>& arrived) {
  constexpr double h = 0.001;
  const int steps = std::max(1, static_cast<int>(std::lround(dt / h)));
  for (int i = 0; i < steps; ++i) {
    while (!commands_in_flight_.empty() && commands_in_flight_.front().first <= t_ + 1e-12) {
      active_ = commands_in_flight_.front().second;
      commands_in_flight_.pop_front();
    }
    integrate(h);
    t_ += h;
    if (t_ + 1e-9 >= next_navdata_) {
      NavdataSample s = sense();
      s.t = t_ + options_.navdata_delay;
      navdata_in_flight_.push_back(s);
      next_navdata_ += options_.navdata_period;
    }
    while (!navdata_in_flight_.empty() && navdata_in_flight_.front().t <= t_ + 1e-12) {
      arrived.push_back(navdata_in_flight_.front());
      navdata_in_flight_.pop_front();
    }
  }
}

PlantInstrument SurrogatePlant::instrument() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Object frame: x to the panel's right (-y world), y down (-z world), z into the panel (+x world).
  T.linear().col(0) = -Eigen::Vector3d::UnitY();
  T.linear().col(1) = -Eigen::Vector3d::UnitZ();
  T.linear().col(2) = Eigen::Vector3d::UnitX();
  T.translation() = Eigen::Vector3d(3.0, 0.0, 1.2);
  return {"surrogate_panel", T};
}

GroundTruth SurrogatePlant::truth() const {
  GroundTruth g;
  g.t = t_;
  g.T_world_body = make_pose(p_, yaw_, pitch_, roll_);
  g.velocity_world = v_;
  g.yaw_rate = yaw_rate_;
  return g;
}

}  // namespace labo::bench
