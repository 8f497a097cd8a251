#include "localization/slam/optimize/pose_graph.hpp"

#include <array>
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <cmath>

namespace labo::slam {
namespace {

struct RelativeSim3Cost {
  RelativeSim3Cost(const Similarity3& measured, double w_rot, double w_trans, double w_scale)
      : R_m_t(measured.R.transpose()), t_m(measured.t), inv_s_m(1.0 / measured.scale), log_s_m(std::log(measured.scale)),
        w_rot(w_rot), w_trans(w_trans), w_scale(w_scale) {}

  template <typename T>
  bool operator()(const T* si, const T* sj, T* residual) const {
    using M3 = Eigen::Matrix<T, 3, 3>;
    using V3 = Eigen::Matrix<T, 3, 1>;
    M3 Ri, Rj;
    ceres::AngleAxisToRotationMatrix(si, ceres::ColumnMajorAdapter3x3(Ri.data()));
    ceres::AngleAxisToRotationMatrix(sj, ceres::ColumnMajorAdapter3x3(Rj.data()));
    const V3 ti(si[3], si[4], si[5]), tj(sj[3], sj[4], sj[5]);
    // S_ij = S_i * S_j^-1: scale s_i / s_j, rotation Ri Rj^T, translation t_i - s_ij R_ij t_j.
    const T log_s_ij = si[6] - sj[6];
    const T s_ij = exp(log_s_ij);
    const M3 R_ij = Ri * Rj.transpose();
    const V3 t_ij = ti - s_ij * (R_ij * tj);
    // E = measured^-1 * S_ij.
    const M3 R_e = R_m_t.cast<T>() * R_ij;
    const V3 t_e = R_m_t.cast<T>() * (t_ij - t_m.cast<T>()) * T(inv_s_m);
    T aa[3];
    ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(R_e.data()), aa);
    for (int k = 0; k < 3; ++k) {
      residual[k] = aa[k] * T(w_rot);
      residual[3 + k] = t_e[k] * T(w_trans);
    }
    residual[6] = (log_s_ij - T(log_s_m)) * T(w_scale);
    return true;
  }

  Eigen::Matrix3d R_m_t;
  Eigen::Vector3d t_m;
  double inv_s_m, log_s_m;
  double w_rot, w_trans, w_scale;
};

}  // namespace

PoseGraphReport optimize_pose_graph(PoseGraph& graph, const PoseGraphSettings& settings) {
  std::map<int, Sim3Parameters> parameters;
  for (const auto& [id, S] : graph.nodes) parameters[id] = to_parameters(S);
  ceres::Problem problem;
  for (const PoseGraphEdge& e : graph.edges) {
    auto a = parameters.find(e.i), b = parameters.find(e.j);
    if (a == parameters.end() || b == parameters.end() || e.i == e.j) continue;
    auto* cost = new ceres::AutoDiffCostFunction<RelativeSim3Cost, 7, 7, 7>(
        new RelativeSim3Cost(e.measured_ij, e.weight / settings.rotation_sigma_rad, e.weight / settings.translation_sigma,
                             e.weight / settings.log_scale_sigma));
    problem.AddResidualBlock(cost, nullptr, a->second.data(), b->second.data());
  }
  PoseGraphReport report;
  if (problem.NumResidualBlocks() == 0) return report;
  bool any_fixed = false;
  for (auto& [id, x] : parameters) {
    if (graph.fixed.count(id) && problem.HasParameterBlock(x.data())) {
      problem.SetParameterBlockConstant(x.data());
      any_fixed = true;
    }
  }
  if (!any_fixed) return report;  // no gauge: the solution would float

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)
                                   ? ceres::SPARSE_NORMAL_CHOLESKY
                                   : ceres::DENSE_QR;
  options.max_num_iterations = settings.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  report.iterations = static_cast<int>(summary.iterations.size());
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  report.solved = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  if (!report.solved) return report;
  for (auto& [id, S] : graph.nodes) {
    const Sim3Parameters& x = parameters[id];
    bool finite = true;
    for (double v : x) finite = finite && std::isfinite(v);
    if (finite) S = from_parameters(x);
  }
  return report;
}

}  // namespace labo::slam
