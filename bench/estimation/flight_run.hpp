#pragma once
// FlightRun: one lockstep flight for the estimation experiments: the plant, an EstimationPipeline
// (the StateEstimator and its visual source) fed with the plant's navdata, frames and the commands
// sent, and a PD position loop on the estimate, one command per 1/30 s like the paper's loop.
#include <cmath>
#include <deque>
#include <memory>
#include <optional>

#include "localization/estimation/command_lag_estimator.hpp"
#include "bench/estimation/estimation_pipeline.hpp"

namespace labo::bench {

class FlightRun {
 public:
  static constexpr Seconds kTick = 1.0 / 30.0;

  // `compensate`: the controller acts on predict_for_control(now); otherwise on predict(now) of an
  // estimator that believes every input is current (all delays 0). The pipeline is made by `make`
  // with the run's configuration.
  FlightRun(EstimationPlant& plant, estimation::EstimatorConfig config, const PipelineFactory& make, unsigned seed,
            bool compensate, const Eigen::Vector3d& initial_error = Eigen::Vector3d::Zero());

  struct Gains {
    double kp = 1.0, kd = 1.2, kz = 1.2, kyaw = 1.5;
    static Gains aggressive() { return {2.5, 2.0, 1.5, 1.5}; }
  };
  void set_gains(const Gains& g) { gains_ = g; }

  void tick();
  void run_for(Seconds duration) { run_until(plant_.now() + duration); }
  void run_until(Seconds t);

  // Knobs of the experiment.
  void set_vision(const VisionWanted& wanted) { pipeline_->set_vision(wanted); }
  std::optional<double> open_loop_gaz;   // overrides the z loop (the scale manoeuvre)
  Eigen::Vector3d setpoint = Eigen::Vector3d(0, 0, 1);
  double setpoint_yaw = 0;

  EstimationPlant& plant() { return plant_; }
  const EstimationPlant& plant() const { return plant_; }
  const estimation::StateEstimator& estimator() const { return pipeline_->estimator(); }
  const EstimationPipeline& pipeline() const { return *pipeline_; }
  estimation::FusedState estimate_now() const { return estimator().predict(plant_.now()); }
  // The true pose at a past time of this run (linear between ticks).
  Eigen::Isometry3d truth_at(Seconds t) const;

  // The estimator's scale (metres per map unit; 0 while not estimated) at time t of this run.
  double estimated_scale_at(Seconds t) const;

  // RMS of |position the controller acted on - true position when that command acted|.
  // The command round trip (control + navdata delay) measured from this run's commands and navdata.
  const estimation::CommandLagEstimator& command_lag() const { return command_lag_; }

  double controller_input_error_rms() const { return input_error_n_ > 0 ? std::sqrt(input_error_sum2_ / input_error_n_) : 0.0; }

 private:
  MoveCommand control(const estimation::FusedState& f) const;

  EstimationPlant& plant_;
  Gains gains_;
  estimation::EstimatorConfig config_;
  std::unique_ptr<EstimationPipeline> pipeline_;
  bool compensate_;
  estimation::CommandLagEstimator command_lag_;
  std::vector<NavdataSample> arrived_;
  std::deque<std::pair<Seconds, Eigen::Vector3d>> controller_inputs_;  // effect time, position used
  std::deque<GroundTruth> history_;  // the last seconds of truth, one per tick
  std::vector<std::pair<Seconds, double>> scale_log_;  // (time, scale) at each change of the scale
  double input_error_sum2_ = 0;
  int input_error_n_ = 0;
};

}  // namespace labo::bench
