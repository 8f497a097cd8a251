#pragma once
// The five pose methods of the paper's Table 1 behind one selectable interface. LmTracking starts the
// Levenberg-Marquardt refinement from the previous frame's pose and falls back to EPnP (+ LM) when
// there is no previous pose or the tracked solution does not fit the landmarks.
#include <optional>
#include <random>
#include <string>
#include <string_view>

#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

enum class PnpMethod { Epnp, RansacP3p, EpnpLm, RansacP3pLm, LmTracking };

std::string_view to_string(PnpMethod method);
// "epnp", "ransac_p3p", "epnp_lm", "ransac_p3p_lm", "lm_tracking"; empty for anything else.
std::optional<PnpMethod> parse_pnp_method(std::string_view text);

struct FacePoseSolverOptions {
  PnpMethod method = PnpMethod::LmTracking;
  RansacOptions ransac;
  LmOptions lm;
  // A tracked pose whose RMS reprojection error exceeds this (pixels, scaled by the face's
  // interocular distance / 60 px) is discarded and the solver re-initialises with EPnP.
  double tracking_max_rms_px = 4.0;
  unsigned seed = 7;
};

struct FacePoseEstimate {
  PnpSolution solution;
  bool reinitialised = false;  // LmTracking fell back to EPnP this frame
};

class FacePoseSolver {
 public:
  explicit FacePoseSolver(FacePoseSolverOptions options = {});

  // `pixel_scale` scales the pixel thresholds for the face's size in the image (1 at 60 px between
  // the eyes). Empty when the method finds no pose in front of the camera.
  std::optional<FacePoseEstimate> solve(const PnpProblem& problem, double pixel_scale = 1.0);
  // Forget the previous pose (face lost): the next LmTracking call initialises from EPnP.
  void reset() { previous_.reset(); }
  bool has_previous() const { return previous_.has_value(); }
  PnpMethod method() const { return options_.method; }

 private:
  std::optional<FacePoseEstimate> initialise(const PnpProblem& problem, const LmOptions& lm);

  FacePoseSolverOptions options_;
  std::mt19937 rng_;
  std::optional<Eigen::Isometry3d> previous_;
};

}  // namespace labo::face
