#include "localization/estimation/eval/flight_run.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo {

namespace {
constexpr double kG = 9.81;
constexpr double kMaxRollPitch = 0.6;

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, double sigma_t, double sigma_r, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Isometry3d out = T;
  out.translation() += sigma_t * Eigen::Vector3d(n(rng), n(rng), n(rng));
  out.linear() = out.linear() * rotation_from_ypr(sigma_r * n(rng), sigma_r * n(rng), sigma_r * n(rng));
  return out;
}
}  // namespace

Eigen::Isometry3d FlightRun::instrument_pose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Object frame: x to the panel's right (-y world), y down (-z world), z into the panel (+x world).
  T.linear().col(0) = -Eigen::Vector3d::UnitY();
  T.linear().col(1) = -Eigen::Vector3d::UnitZ();
  T.linear().col(2) = Eigen::Vector3d::UnitX();
  T.translation() = Eigen::Vector3d(3.0, 0.0, 1.2);
  return T;
}

FlightRun::FlightRun(EstimationPlant& plant, EstimatorConfig config, const VisionThresholds& thresholds,
                     unsigned seed, bool compensate, const Eigen::Vector3d& initial_error)
    : plant_(plant), config_([&] {
        if (!compensate) config.video_delay_s = config.navdata_delay_s = config.control_delay_s = 0.0;
        return config;
      }()),
      estimator_(config_, thresholds), compensate_(compensate), rng_(seed * 7919u + 13u) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  T_map_world_ = make_pose(Eigen::Vector3d(u(rng_), u(rng_), u(rng_)), M_PI * u(rng_), 0.3 * u(rng_), 0.3 * u(rng_));
  metres_per_unit_ = std::exp(std::log(0.4) + (std::log(2.5) - std::log(0.4)) * 0.5 * (u(rng_) + 1.0));
  Eigen::Isometry3d start = plant_.truth().T_world_body;
  start.translation() += initial_error;
  estimator_.set_surface_map(plant_.surfaces());
  estimator_.reset(start, plant_.now() - config_.navdata_delay_s);
}

MoveCommand FlightRun::control(const FusedState& f) const {
  const Eigen::Vector3d e = setpoint - f.position_world;
  const Eigen::Vector2d a = gains_.kp * e.head<2>() - gains_.kd * f.velocity_world.head<2>();
  const double tilt_max = config_.model.tilt_max_rad;
  const Eigen::Vector2d forward(std::cos(f.yaw), std::sin(f.yaw)), left(-std::sin(f.yaw), std::cos(f.yaw));
  MoveCommand c;
  c.pitch = std::clamp(a.dot(forward) / (kG * tilt_max), -kMaxRollPitch, kMaxRollPitch);
  c.roll = std::clamp(-a.dot(left) / (kG * tilt_max), -kMaxRollPitch, kMaxRollPitch);  // roll > 0 moves right
  c.gaz = open_loop_gaz ? *open_loop_gaz : std::clamp(gains_.kz * e.z() - 0.3 * f.velocity_world.z(), -1.0, 1.0);
  c.yaw_rate = std::clamp(gains_.kyaw * wrap_angle(setpoint_yaw - f.yaw), -1.0, 1.0);
  return c;
}

void FlightRun::deliver_frames() {
  while (!frames_.empty() && frames_.front().first <= plant_.now() + 1e-9) {
    const auto [t_arrival, T_world_body] = frames_.front();
    frames_.pop_front();
    const Eigen::Isometry3d T_world_cam = T_world_body * T_body_cam_front();
    if (slam_visible) {
      SlamObservation o;
      o.t = t_arrival;
      Eigen::Isometry3d T = T_map_world_ * perturbed(T_world_cam, 0.015, 0.5 * M_PI / 180.0, rng_);
      T.translation() /= metres_per_unit_;
      o.T_map_cam = T;
      o.quality = 0.8;
      estimator_.add_slam_pose(o);
    }
    if (object_visible_when_in_view) {
      const Eigen::Isometry3d T_cam_object = T_world_cam.inverse() * instrument_pose();
      const Eigen::Vector3d p = T_cam_object.translation();
      const double d = p.norm();
      if (p.z() > 0.2 && std::abs(p.x() / p.z()) < 0.8 && std::abs(p.y() / p.z()) < 0.45 && d < 4.0) {
        ObjectObservation o;
        o.t = t_arrival;
        o.object_index = 0;
        o.T_cam_object = perturbed(T_cam_object, 0.003 + 0.004 * d * d, 0.7 * M_PI / 180.0, rng_);
        o.T_world_object_surveyed = instrument_pose();
        o.quality = 0.9;
        estimator_.add_object_pose(o);
      }
    }
  }
}

void FlightRun::tick() {
  arrived_.clear();
  plant_.step(kTick, arrived_);
  for (const NavdataSample& n : arrived_) estimator_.add_navdata(n);
  frames_.emplace_back(plant_.now() + kTrueVideoDelay, plant_.truth().T_world_body);
  deliver_frames();
  const Seconds now = plant_.now();
  while (!controller_inputs_.empty() && controller_inputs_.front().first <= now + 1e-6) {
    input_error_sum2_ += (controller_inputs_.front().second - plant_.truth().T_world_body.translation()).squaredNorm();
    ++input_error_n_;
    controller_inputs_.pop_front();
  }
  const FusedState f = compensate_ ? estimator_.predict_for_control(now) : estimator_.predict(now);
  controller_inputs_.emplace_back(now + kTrueControlDelay, f.position_world);
  const MoveCommand c = control(f);
  plant_.move(c);
  estimator_.add_command(c, now);
}

void FlightRun::run_until(Seconds t) {
  while (plant_.now() < t - 1e-9) tick();
}

}  // namespace labo
