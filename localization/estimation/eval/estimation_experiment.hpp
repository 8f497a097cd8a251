#pragma once
// The lockstep experiments behind `labodrone sim estimate`: a plant (EstimationPlant), the
// StateEstimator fed with its navdata, the commands and visual poses, and a plain PD position loop
// (for the experiments only; the real autopilot is control/'s) closing the loop on the estimate.
//
// Visual poses: until the SLAM and planar pipelines run on the simulated lab's rendered frames, they
// are derived from the plant's ground truth with realistic noise and the video delay (SLAM: an
// arbitrary map frame and scale, ~1.5 cm / 0.5 deg; the instrument: noise growing with distance^2,
// only while it is in the front camera's field of view). Each result says so in `vision_input`.
#include <functional>
#include <memory>
#include <string>

#include "localization/estimation/estimation_config.hpp"
#include "localization/estimation/eval/estimation_plant.hpp"
#include "localization/vision_thresholds.hpp"

namespace labo {

struct ImpulseResult {
  double peak_displacement_m = 0;   // largest |z - set point| of the drone after the push
  bool returned = false;            // drone and estimate within 0.1 m of the set point, held 1 s
  double return_time_s = -1;        // from the push until then
  double final_estimate_error_m = 0;
};

// Over a phase of flight: the estimate vs the truth, and the drone vs its set point.
struct TrackingErrors {
  double position_rmse_m = 0;
  double yaw_rmse_deg = 0;
  double control_rmse_m = 0;
};

struct EstimationResults {
  std::string plant;
  std::string vision_input;
  // Stage 1: the up/down manoeuvre.
  double scale_error_percent = 0;
  double scale_accuracy = 0;
  int scale_pairs = 0;
  // Hovering with SLAM.
  TrackingErrors hover_slam;
  // Servoing 0.8 m in front of an instrument on its homography.
  TrackingErrors servo;
  // Dead reckoning (vision lost) while flying a small square.
  double dead_reckoning_drift_m_per_s = 0;
  double dead_reckoning_yaw_drift_deg_per_s = 0;
  // z impulses of +0.5 m.
  ImpulseResult impulse_servo;           // while servoing on the instrument
  ImpulseResult impulse_dead_reckoning;  // with navdata only
  ImpulseResult impulse_paper_rule;      // navdata only, the paper's gamma rule
  // Delay compensation: the drone's set-point error with it and without it.
  double control_rmse_compensated_m = 0;
  double control_rmse_uncompensated_m = 0;
  // What compensation targets: the controller's input vs the true position when its command acts.
  double controller_input_error_compensated_m = 0;
  double controller_input_error_uncompensated_m = 0;
  std::uint64_t rejected_inputs = 0;
};

// A fresh plant for a seed, sending navdata every `navdata_period` seconds.
using PlantFactory = std::function<std::unique_ptr<EstimationPlant>(unsigned seed, Seconds navdata_period)>;

EstimationResults run_estimation_experiments(const PlantFactory& make_plant, unsigned seed,
                                             const EstimatorConfig& config, const VisionThresholds& thresholds);

}  // namespace labo
