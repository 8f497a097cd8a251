#pragma once
// The standard corner-perturbation sweep (Baker & Matthews' frequency of convergence, homography
// version): a square template sits at the centre of a textured 640x480 scene through a homography
// whose four corners are perturbed by N(0, sigma^2) per axis; each tracker starts from the
// unperturbed placement and must bring the corners back. Converged when the tracker reports success
// and the corner RMS (root of the mean squared point distance over the 4 corners) is <= 1 px.
#include <cstdint>
#include <vector>

#include "localization/planar/planar_config.hpp"

namespace labo::bench {

struct PerturbationSettings {
  int template_side_px = 200;
  int scene_width_px = 640, scene_height_px = 480;
  std::vector<double> sigmas_px;  // default 1..20
  int trials = 100;
  double converged_rms_px = 1.0;
  double pixel_noise = 2.0;  // grey levels, added to the scene
  std::uint32_t seed = 7;
};

struct TrackerSweepStats {
  double convergence_rate = 0;        // fraction of trials
  double mean_converged_rms_px = 0;   // over converged trials
  double median_converged_rms_px = 0;
  double median_ms = 0, mean_ms = 0;  // per call, wall time
  double mean_iterations = 0;         // 0 when the tracker does not report it (ECC)
};

struct PerturbationRow {
  double sigma_px = 0;
  TrackerSweepStats ecc, ic;
};

std::vector<PerturbationRow> run_perturbation_sweep(const PerturbationSettings& settings, const planar::PlanarConfig& config);

}  // namespace labo::bench
