#include "localization/face/face_pose_solver.hpp"

#include <array>

namespace labo::face {

namespace {
struct MethodName {
  PnpMethod method;
  std::string_view name;
};
constexpr std::array<MethodName, 5> kMethodNames{{{PnpMethod::Epnp, "epnp"},
                                                  {PnpMethod::RansacP3p, "ransac_p3p"},
                                                  {PnpMethod::EpnpLm, "epnp_lm"},
                                                  {PnpMethod::RansacP3pLm, "ransac_p3p_lm"},
                                                  {PnpMethod::LmTracking, "lm_tracking"}}};
}  // namespace

std::string_view to_string(PnpMethod method) {
  for (const auto& m : kMethodNames) {
    if (m.method == method) return m.name;
  }
  return "unknown";
}

std::optional<PnpMethod> parse_pnp_method(std::string_view text) {
  for (const auto& m : kMethodNames) {
    if (m.name == text) return m.method;
  }
  return std::nullopt;
}

FacePoseSolver::FacePoseSolver(FacePoseSolverOptions options) : options_(options), rng_(options.seed) {}

std::optional<FacePoseEstimate> FacePoseSolver::initialise(const PnpProblem& problem, const LmOptions& lm) {
  auto epnp = solve_epnp(problem);
  if (!epnp) return std::nullopt;
  auto refined = refine_lm(problem, epnp->T_cam_face, lm);
  if (!refined) return std::nullopt;
  return FacePoseEstimate{*refined, true};
}

std::optional<FacePoseEstimate> FacePoseSolver::solve(const PnpProblem& problem, double pixel_scale) {
  LmOptions lm = options_.lm;
  lm.huber_px *= pixel_scale;
  RansacOptions ransac = options_.ransac;
  ransac.inlier_threshold_px *= pixel_scale;

  std::optional<FacePoseEstimate> out;
  switch (options_.method) {
    case PnpMethod::Epnp:
      if (auto s = solve_epnp(problem)) out = FacePoseEstimate{*s, false};
      break;
    case PnpMethod::RansacP3p:
      if (auto s = solve_ransac_p3p(problem, ransac, rng_)) out = FacePoseEstimate{*s, false};
      break;
    case PnpMethod::EpnpLm:
      if (auto s = solve_epnp(problem)) {
        if (auto r = refine_lm(problem, s->T_cam_face, lm)) out = FacePoseEstimate{*r, false};
      }
      break;
    case PnpMethod::RansacP3pLm:
      if (auto s = solve_ransac_p3p(problem, ransac, rng_)) {
        // All points, not only the minimal sample's inliers: the Huber weights already discount the
        // outliers, and a tight inlier set at small faces throws away good landmarks.
        if (auto r = refine_lm(problem, s->T_cam_face, lm)) out = FacePoseEstimate{*r, false};
      }
      break;
    case PnpMethod::LmTracking:
      if (previous_) {
        auto tracked = refine_lm(problem, *previous_, lm);
        if (tracked && tracked->rms_px <= options_.tracking_max_rms_px * pixel_scale) {
          out = FacePoseEstimate{*tracked, false};
        }
      }
      if (!out) out = initialise(problem, lm);
      break;
  }
  if (out) {
    previous_ = out->solution.T_cam_face;
  } else {
    previous_.reset();
  }
  return out;
}

}  // namespace labo::face
