#include "localization/slam/optimize/sim3_solver.hpp"

#include <array>
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <cmath>
#include <random>

namespace labo::slam {
namespace {

// Closed-form similarity (Umeyama) mapping `from` onto `to`; empty when degenerate.
std::optional<Similarity3> fit_similarity(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to) {
  const Eigen::Matrix4d M = Eigen::umeyama(from, to, true);
  if (!M.allFinite()) return std::nullopt;
  Similarity3 G;
  G.scale = M.block<3, 1>(0, 0).norm();
  if (!(G.scale > 1e-6) || !std::isfinite(G.scale)) return std::nullopt;
  G.R = M.block<3, 3>(0, 0) / G.scale;
  G.t = M.block<3, 1>(0, 3);
  return G;
}

struct PairErrors {
  double current_chi2 = 1e9, old_chi2 = 1e9;
};

// Reprojection of each side's transformed point in the other keyframe, in squared sigmas.
PairErrors pair_errors(const IdealCamera& camera, const Sim3Pair& p, const Similarity3& G, const Similarity3& G_inv,
                       const Eigen::Isometry3d& T_cur, const Eigen::Isometry3d& T_old) {
  PairErrors e;
  if (const auto px = camera.project(T_old * (G * p.current_point))) {
    e.old_chi2 = (*px - p.old_px).squaredNorm() / (p.old_sigma * p.old_sigma);
  }
  if (const auto px = camera.project(T_cur * (G_inv * p.old_point))) {
    e.current_chi2 = (*px - p.current_px).squaredNorm() / (p.current_sigma * p.current_sigma);
  }
  return e;
}

std::vector<int> inliers_of(const IdealCamera& camera, const std::vector<Sim3Pair>& pairs, const Similarity3& G,
                            const Eigen::Isometry3d& T_cur, const Eigen::Isometry3d& T_old, double gate) {
  const Similarity3 G_inv = G.inverse();
  std::vector<int> out;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairErrors e = pair_errors(camera, pairs[i], G, G_inv, T_cur, T_old);
    if (e.current_chi2 <= gate && e.old_chi2 <= gate) out.push_back(static_cast<int>(i));
  }
  return out;
}

// Both reprojections of one pair as a function of G = (angle-axis, translation, log scale).
struct PairReprojectionCost {
  PairReprojectionCost(const Sim3Pair& p, const Eigen::Isometry3d& T_cur, const Eigen::Isometry3d& T_old, const IdealCamera& c)
      : pair(p), T_cur(T_cur), T_old(T_old), fx(c.fx()), fy(c.fy()), cx(c.cx()), cy(c.cy()) {}

  template <typename T>
  bool operator()(const T* g, T* residual) const {
    using V3 = Eigen::Matrix<T, 3, 1>;
    const T s = exp(g[6]);
    // old side: T_old * (s R X_cur + t)
    T x[3] = {T(pair.current_point.x()), T(pair.current_point.y()), T(pair.current_point.z())}, rx[3];
    ceres::AngleAxisRotatePoint(g, x, rx);
    const V3 in_old_map(s * rx[0] + g[3], s * rx[1] + g[4], s * rx[2] + g[5]);
    const V3 in_old_cam = T_old.linear().cast<T>() * in_old_map + T_old.translation().cast<T>();
    // current side: T_cur * R^T (X_old - t) / s
    const T minus_aa[3] = {-g[0], -g[1], -g[2]};
    T y[3] = {T(pair.old_point.x()) - g[3], T(pair.old_point.y()) - g[4], T(pair.old_point.z()) - g[5]}, ry[3];
    ceres::AngleAxisRotatePoint(minus_aa, y, ry);
    const V3 in_cur_map(ry[0] / s, ry[1] / s, ry[2] / s);
    const V3 in_cur_cam = T_cur.linear().cast<T>() * in_cur_map + T_cur.translation().cast<T>();
    if (in_old_cam.z() < T(1e-6) || in_cur_cam.z() < T(1e-6)) {
      for (int k = 0; k < 4; ++k) residual[k] = T(0);
      return true;
    }
    residual[0] = (T(fx) * in_old_cam.x() / in_old_cam.z() + T(cx) - T(pair.old_px.x())) / T(pair.old_sigma);
    residual[1] = (T(fy) * in_old_cam.y() / in_old_cam.z() + T(cy) - T(pair.old_px.y())) / T(pair.old_sigma);
    residual[2] = (T(fx) * in_cur_cam.x() / in_cur_cam.z() + T(cx) - T(pair.current_px.x())) / T(pair.current_sigma);
    residual[3] = (T(fy) * in_cur_cam.y() / in_cur_cam.z() + T(cy) - T(pair.current_px.y())) / T(pair.current_sigma);
    return true;
  }

  Sim3Pair pair;
  Eigen::Isometry3d T_cur, T_old;
  double fx, fy, cx, cy;
};

Similarity3 refine(const IdealCamera& camera, const std::vector<Sim3Pair>& pairs, const std::vector<int>& inliers,
                   const Similarity3& G0, const Eigen::Isometry3d& T_cur, const Eigen::Isometry3d& T_old) {
  Sim3Parameters g = to_parameters(G0);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::HuberLoss loss(std::sqrt(5.991));
  for (int i : inliers) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PairReprojectionCost, 4, 7>(
                                 new PairReprojectionCost(pairs[static_cast<std::size_t>(i)], T_cur, T_old, camera)),
                             &loss, g.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 10;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  for (double v : g) {
    if (!std::isfinite(v)) return G0;
  }
  if (!summary.IsSolutionUsable()) return G0;
  return from_parameters(g);
}

}  // namespace

std::optional<Sim3Estimate> solve_sim3(const IdealCamera& camera, const std::vector<Sim3Pair>& pairs,
                                       const Eigen::Isometry3d& T_cur, const Eigen::Isometry3d& T_old,
                                       const Sim3SolverSettings& settings) {
  if (static_cast<int>(pairs.size()) < std::max(3, settings.min_inliers)) return std::nullopt;
  std::mt19937 rng(settings.seed);
  std::uniform_int_distribution<std::size_t> pick(0, pairs.size() - 1);
  std::optional<Similarity3> best;
  std::size_t best_count = 0;
  Eigen::Matrix3Xd from(3, 3), to(3, 3);
  for (int it = 0; it < settings.iterations; ++it) {
    const std::size_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || b == c || a == c) continue;
    from << pairs[a].current_point, pairs[b].current_point, pairs[c].current_point;
    to << pairs[a].old_point, pairs[b].old_point, pairs[c].old_point;
    const auto G = fit_similarity(from, to);
    if (!G) continue;
    const std::size_t count = inliers_of(camera, pairs, *G, T_cur, T_old, settings.chi2_gate).size();
    if (count > best_count) {
      best_count = count;
      best = G;
    }
  }
  if (!best || static_cast<int>(best_count) < settings.min_inliers) return std::nullopt;
  // Closed form on all inliers, then the reprojection refinement, re-gating in between.
  std::vector<int> inliers = inliers_of(camera, pairs, *best, T_cur, T_old, settings.chi2_gate);
  Eigen::Matrix3Xd all_from(3, static_cast<Eigen::Index>(inliers.size())), all_to(3, static_cast<Eigen::Index>(inliers.size()));
  for (std::size_t k = 0; k < inliers.size(); ++k) {
    all_from.col(static_cast<Eigen::Index>(k)) = pairs[static_cast<std::size_t>(inliers[k])].current_point;
    all_to.col(static_cast<Eigen::Index>(k)) = pairs[static_cast<std::size_t>(inliers[k])].old_point;
  }
  Similarity3 G = *best;
  if (const auto closed = fit_similarity(all_from, all_to)) {
    if (inliers_of(camera, pairs, *closed, T_cur, T_old, settings.chi2_gate).size() >= inliers.size()) G = *closed;
  }
  inliers = inliers_of(camera, pairs, G, T_cur, T_old, settings.chi2_gate);
  G = refine(camera, pairs, inliers, G, T_cur, T_old);
  inliers = inliers_of(camera, pairs, G, T_cur, T_old, settings.chi2_gate);
  if (static_cast<int>(inliers.size()) < settings.min_inliers) return std::nullopt;
  return Sim3Estimate{G, std::move(inliers)};
}

}  // namespace labo::slam
