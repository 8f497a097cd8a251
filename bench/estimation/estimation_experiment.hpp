#pragma once
// The lockstep experiments behind `labodrone-bench sim estimate`: a plant (EstimationPlant), an
// EstimationPipeline (the StateEstimator and its visual source: truth-derived poses or the real
// front-ends on rendered frames) fed with the plant's navdata, frames and the commands sent, and a
// plain PD position loop (for the experiments only; the real autopilot is control/'s) closing the
// loop on the estimate. Each result says which plant and which vision produced it.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "localization/estimation/estimation_config.hpp"
#include "bench/estimation/estimation_pipeline.hpp"

namespace labo::bench {

struct ImpulseResult {
  double push_mps = 0;              // the upward velocity change applied
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

// The map's true scale over a window of the SLAM run and the estimator's at its end (0: no map, or
// no scale yet).
struct ScaleWindow {
  Seconds from_s = 0;  // since SLAM was started
  double true_m_per_unit = 0;
  double estimated_m_per_unit = 0;
};

// Dead reckoning across the lab's bare floor, where the bottom camera's velocity drops out: a set
// point moving at 0.5 m/s along x over it (the estimate's error is what grew since the crossing began).
struct BareFloorCrossing {
  double final_error_m = 0;    // horizontal, 2 s after the set point stopped
  double max_error_m = 0;      // horizontal, over the crossing and the 2 s
  double overshoot_m = 0;      // how far the drone went past the set point's end along x
  std::uint64_t dropouts = 0;  // the estimator's velocity_dropouts / velocity_dropout_packets
  std::uint64_t dropout_packets = 0;
  std::string crash;           // what the drone hit, if it did
};

struct EstimationResults {
  std::string plant;
  std::string vision_input;
  // Stage 1: the up/down manoeuvre and a forward/back leg. The map's true scale is fitted (similarity,
  // Umeyama) between the SLAM camera positions and the true ones over the return leg (the map's scale
  // at the end of the manoeuvre); the error is the estimator's against it.
  double scale_error_percent = 0;
  double scale_true_m_per_unit = 0;
  double scale_estimated_m_per_unit = 0;
  bool scale_estimated = false;
  double scale_accuracy = 0;
  int scale_pairs = 0;
  int scale_outliers = 0;  // pairs the gate refused when they came, up to the end of stage 1
  int scale_changes = 0;   // times the map's scale was found to have changed (estimate restarted)
  // Hovering with SLAM, and the scale then: the estimate at the end against the map's scale over the
  // flight to the hover point and the hover.
  TrackingErrors hover_slam;
  double scale_true_hover_m_per_unit = 0;
  double scale_error_hover_percent = 0;
  std::vector<ScaleWindow> scale_windows;  // from the start of SLAM to the end of the hover
  // Servoing 0.8 m in front of an instrument on its homography.
  TrackingErrors servo;
  // Dead reckoning (vision lost) while flying a small square.
  double dead_reckoning_drift_m_per_s = 0;
  double dead_reckoning_yaw_drift_deg_per_s = 0;
  // Across the bare floor, with the velocity dropout detected and fusing every velocity (no detection).
  BareFloorCrossing bare_floor;
  BareFloorCrossing bare_floor_fusing_every_velocity;
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
  // The same hold with the control delay set from the measured round trip (0 when none was measured).
  double control_delay_measured_s = 0;   // round trip minus the configured navdata delay
  double control_rmse_measured_delay_m = 0;
  double controller_input_error_measured_delay_m = 0;
  // The command round trip (control + navdata delay) as measured by CommandLagEstimator during the
  // compensated hold, against the plant's own (command latency + navdata delay) and the configured one.
  double round_trip_measured_s = 0;      // 0 when no window was accepted
  std::uint64_t round_trip_windows = 0;
  double round_trip_true_s = 0;
  double round_trip_configured_s = 0;
  std::uint64_t rejected_inputs = 0;
  std::map<std::string, std::uint64_t> rejections;  // by the estimator's counter name, over all runs
};

// A fresh plant for one run.
using PlantFactory = std::function<std::unique_ptr<EstimationPlant>(const PlantRequest& request)>;

// Which phases to run: all, or only stage 1 and the SLAM hover (the scale and hover figures; the
// real-vision campaigns, where every frame is rendered and tracked, are several times cheaper so).
enum class ExperimentPhases { All, SlamOnly };

EstimationResults run_estimation_experiments(const PlantFactory& make_plant, const PipelineKind& vision, unsigned seed,
                                             const estimation::EstimatorConfig& config,
                                             ExperimentPhases phases = ExperimentPhases::All);

}  // namespace labo::bench
