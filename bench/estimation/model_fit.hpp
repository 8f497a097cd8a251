#pragma once
// Refits the estimator's motion-model constants (MotionModelConstants) on a plant, from what a real
// flight also provides: the commands sent and the navdata received, aligned with the link delays.
// Random command steps excite each axis (a PD on the true position keeps the flight near its start);
// each first-order law is a linear least-squares problem:
//   roll' = a (b u - roll)          -> regress roll' on [u, roll]          (pitch pooled with roll)
//   yawrate' = a (b u - yawrate)     -> yaw rate from navdata yaw differences
//   vz' = a (b u - vz)
//   a_body = g_eff f_body - d v_body -> horizontal, in the yaw-aligned body frame (rotation removed)
// The report gives the constants and each law's residual with the previous and the fitted constants,
// on held-out data (the second half of the flight).
#include <string>
#include <vector>

#include "localization/estimation/estimation_config.hpp"
#include "bench/estimation/estimation_plant.hpp"

namespace labo::bench {

struct ModelFitLaw {
  std::string name;
  double residual_rms_before = 0;  // held-out, with the constants given
  double residual_rms_after = 0;   // held-out, with the fitted constants
  int samples = 0;
};

struct ModelFitReport {
  estimation::MotionModelConstants before;
  estimation::MotionModelConstants fitted;
  std::vector<ModelFitLaw> laws;
  double flight_s = 0;
};

// The navdata and command delays are the plant's own (what a link measurement would give).
ModelFitReport fit_motion_model(EstimationPlant& plant, const estimation::MotionModelConstants& before, Seconds duration = 120.0,
                                unsigned seed = 1);

}  // namespace labo::bench
