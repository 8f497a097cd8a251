#pragma once
// FlightRun: one lockstep flight for the estimation experiments: the plant, the StateEstimator fed
// with navdata, commands and (ground-truth-derived, noisy, delayed) visual poses, and a PD position
// loop on the estimate, one command per 1/30 s like the paper's loop.
#include <cmath>
#include <deque>
#include <optional>
#include <random>

#include "localization/estimation/eval/estimation_plant.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo {

class FlightRun {
 public:
  static constexpr Seconds kTick = 1.0 / 30.0;
  static constexpr Seconds kTrueVideoDelay = 0.075;

  // `compensate`: the controller acts on predict_for_control(now); otherwise on predict(now) of an
  // estimator that believes every input is current (all delays 0).
  FlightRun(EstimationPlant& plant, EstimatorConfig config, const VisionThresholds& thresholds, unsigned seed,
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
  bool slam_visible = false;
  bool object_visible_when_in_view = false;
  std::optional<double> open_loop_gaz;   // overrides the z loop (the scale manoeuvre)
  Eigen::Vector3d setpoint = Eigen::Vector3d(0, 0, 1);
  double setpoint_yaw = 0;

  EstimationPlant& plant() { return plant_; }
  StateEstimator& estimator() { return estimator_; }
  FusedState estimate_now() const { return estimator_.predict(plant_.now()); }
  double map_metres_per_unit() const { return metres_per_unit_; }

  static Eigen::Isometry3d instrument_pose();
  // RMS of |position the controller acted on - true position when that command acted|.
  double controller_input_error_rms() const { return input_error_n_ > 0 ? std::sqrt(input_error_sum2_ / input_error_n_) : 0.0; }
  static constexpr Seconds kTrueControlDelay = 0.100;  // the surrogate's command delay  // the panel of the experiments, facing the base

 private:
  MoveCommand control(const FusedState& f) const;
  void deliver_frames();

  EstimationPlant& plant_;
  Gains gains_;
  EstimatorConfig config_;
  StateEstimator estimator_;
  bool compensate_;
  std::mt19937 rng_;
  Eigen::Isometry3d T_map_world_;
  double metres_per_unit_;
  std::deque<std::pair<Seconds, Eigen::Isometry3d>> frames_;  // arrival time, body pose at capture
  std::vector<NavdataSample> arrived_;
  std::deque<std::pair<Seconds, Eigen::Vector3d>> controller_inputs_;  // effect time, position used
  double input_error_sum2_ = 0;
  int input_error_n_ = 0;
};

}  // namespace labo
