#include "bench/estimation/flight_run.hpp"

#include <algorithm>
#include <cmath>

#include "core/frames.hpp"

namespace labo::bench {

namespace {
constexpr double kG = 9.81;
constexpr double kMaxRollPitch = 0.6;
constexpr Seconds kHistory = 60.0;  // truth kept for truth_at()
}  // namespace

FlightRun::FlightRun(EstimationPlant& plant, estimation::EstimatorConfig config, const PipelineFactory& make, unsigned seed,
                     bool compensate, const Eigen::Vector3d& initial_error)
    : plant_(plant), config_([&] {
        if (!compensate) config.video_delay_s = config.navdata_delay_s = config.control_delay_s = 0.0;
        return config;
      }()),
      pipeline_(make(config_, plant, seed)), compensate_(compensate), command_lag_(config_.model) {
  Eigen::Isometry3d start = plant_.truth().T_world_body;
  start.translation() += initial_error;
  pipeline_->reset(start, plant_.now() - config_.navdata_delay_s);
  history_.push_back(plant_.truth());
}

MoveCommand FlightRun::control(const estimation::FusedState& f) const {
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

Eigen::Isometry3d FlightRun::truth_at(Seconds t) const {
  const auto later = std::lower_bound(history_.begin(), history_.end(), t,
                                      [](const GroundTruth& g, Seconds x) { return g.t < x; });
  if (later == history_.begin()) return history_.front().T_world_body;
  if (later == history_.end()) return history_.back().T_world_body;
  const GroundTruth& a = *(later - 1);
  const GroundTruth& b = *later;
  const double w = (t - a.t) / std::max(1e-9, b.t - a.t);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = (1.0 - w) * a.T_world_body.translation() + w * b.T_world_body.translation();
  T.linear() = Eigen::Quaterniond(a.T_world_body.linear()).slerp(w, Eigen::Quaterniond(b.T_world_body.linear())).toRotationMatrix();
  return T;
}

void FlightRun::tick() {
  arrived_.clear();
  plant_.step(kTick, arrived_);
  for (const NavdataSample& n : arrived_) {
    pipeline_->on_navdata(n);
    command_lag_.add_navdata(n);
  }
  for (const VideoFrame& frame : plant_.frames_of_last_step()) pipeline_->on_frame(frame);
  const Seconds now = plant_.now();
  const GroundTruth truth = plant_.truth();
  pipeline_->on_truth(truth, now);
  const estimation::ScaleStatus& scale = estimator().scale_status();
  const double scale_now = scale.estimated ? scale.scale : 0.0;
  if (scale_log_.empty() || scale_log_.back().second != scale_now) scale_log_.emplace_back(now, scale_now);
  history_.push_back(truth);
  while (history_.front().t < now - kHistory) history_.pop_front();
  while (!controller_inputs_.empty() && controller_inputs_.front().first <= now + 1e-6) {
    input_error_sum2_ += (controller_inputs_.front().second - truth.T_world_body.translation()).squaredNorm();
    ++input_error_n_;
    controller_inputs_.pop_front();
  }
  const estimation::FusedState f = compensate_ ? estimator().predict_for_control(now) : estimator().predict(now);
  controller_inputs_.emplace_back(now + plant_.command_latency(), f.position_world);
  const MoveCommand c = control(f);
  plant_.move(c);
  pipeline_->on_command(c, now);
  command_lag_.add_command(c, now);
}

double FlightRun::estimated_scale_at(Seconds t) const {
  const auto after = std::upper_bound(scale_log_.begin(), scale_log_.end(), t,
                                      [](Seconds x, const std::pair<Seconds, double>& e) { return x < e.first; });
  return after == scale_log_.begin() ? 0.0 : std::prev(after)->second;
}

void FlightRun::run_until(Seconds t) {
  while (plant_.now() < t - 1e-9) tick();
}

}  // namespace labo::bench
