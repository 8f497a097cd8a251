#include "localization/slam/optimize/bundle_adjuster.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

namespace labo::slam {
namespace {

struct ReprojectionCost {
  ReprojectionCost(const Eigen::Vector2d& px, double sigma, double fx, double fy, double cx, double cy)
      : u(px.x()), v(px.y()), inv_sigma(1.0 / sigma), fx(fx), fy(fy), cx(cx), cy(cy) {}

  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    p[0] += pose[3];
    p[1] += pose[4];
    p[2] += pose[5];
    if (p[2] < T(1e-6)) {
      residual[0] = residual[1] = T(0);  // behind the camera: flagged as outlier afterwards
      return true;
    }
    residual[0] = (T(fx) * p[0] / p[2] + T(cx) - T(u)) * T(inv_sigma);
    residual[1] = (T(fy) * p[1] / p[2] + T(cy) - T(v)) * T(inv_sigma);
    return true;
  }

  double u, v, inv_sigma, fx, fy, cx, cy;
};

// The IMU's gravity direction in the camera against the map's, rotated by the keyframe's pose:
// a tilt error of a radians gives a residual of ~a / sigma (the component along "down" stays ~0).
struct GravityCost {
  GravityCost(const Eigen::Vector3d& down_cam, double sigma) : measured(down_cam), inv_sigma(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* pose, const T* down_map, T* residual) const {
    T d[3];
    ceres::AngleAxisRotatePoint(pose, down_map, d);
    for (int i = 0; i < 3; ++i) residual[i] = (d[i] - T(measured[i])) * T(inv_sigma);
    return true;
  }

  Eigen::Vector3d measured;
  double inv_sigma;
};

class AbortCallback : public ceres::IterationCallback {
 public:
  explicit AbortCallback(const std::atomic<bool>* abort) : abort_(abort) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return abort_ && abort_->load() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::atomic<bool>* abort_;
};

using Pose6 = std::array<double, 6>;

}  // namespace

BundleReport solve_bundle(const IdealCamera& camera, BundleProblem& problem, const BundleSettings& settings,
                          const std::atomic<bool>* abort) {
  std::map<int, Pose6> pose_params;
  for (const auto& [id, T] : problem.poses) {
    Pose6 x{};
    const Eigen::AngleAxisd aa(T.linear());
    const Eigen::Vector3d r = aa.angle() * aa.axis();
    x = {r.x(), r.y(), r.z(), T.translation().x(), T.translation().y(), T.translation().z()};
    pose_params[id] = x;
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  ceres::HuberLoss loss(settings.huber_px);
  for (const BundleObservation& o : problem.observations) {
    auto pose = pose_params.find(o.keyframe);
    auto point = problem.points.find(o.point);
    if (pose == pose_params.end() || point == problem.points.end()) continue;
    auto* cost = new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 6, 3>(
        new ReprojectionCost(o.px, o.sigma, camera.fx(), camera.fy(), camera.cx(), camera.cy()));
    ceres_problem.AddResidualBlock(cost, &loss, pose->second.data(), point->second.data());
  }
  for (auto& [id, x] : pose_params) {
    if (ceres_problem.HasParameterBlock(x.data()) && problem.pose_fixed[id]) {
      ceres_problem.SetParameterBlockConstant(x.data());
    }
  }
  // Gravity prior: on the keyframes that move (a fixed keyframe's term is constant unless the map's
  // gravity direction is estimated). No robust loss: the IMU's attitude has no outliers the way
  // matches do, and its error does not grow with what the images say.
  std::array<double, 3> down_map{};
  const bool gravity = problem.gravity_sigma_rad > 0 && problem.down_map.has_value();
  if (gravity) {
    const Eigen::Vector3d d = problem.down_map->normalized();
    down_map = {d.x(), d.y(), d.z()};
    int terms = 0;
    for (const auto& [id, down_cam] : problem.down_cam) {
      auto pose = pose_params.find(id);
      if (pose == pose_params.end() || !ceres_problem.HasParameterBlock(pose->second.data())) continue;
      if (problem.pose_fixed[id] && problem.down_map_fixed) continue;
      auto* cost = new ceres::AutoDiffCostFunction<GravityCost, 3, 6, 3>(new GravityCost(down_cam, problem.gravity_sigma_rad));
      ceres_problem.AddResidualBlock(cost, nullptr, pose->second.data(), down_map.data());
      ++terms;
    }
    if (terms > 0) {
      if (problem.down_map_fixed) ceres_problem.SetParameterBlockConstant(down_map.data());
      else ceres_problem.SetManifold(down_map.data(), new ceres::SphereManifold<3>());
    }
  }
  BundleReport report;
  if (ceres_problem.NumResidualBlocks() == 0) return report;

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
    options.linear_solver_type = ceres::DENSE_SCHUR;
  }
  options.max_num_iterations = settings.max_iterations;
  options.num_threads = 1;  // deterministic, and the other core belongs to tracking
  options.minimizer_progress_to_stdout = false;
  options.logging_type = ceres::SILENT;
  AbortCallback callback(abort);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &ceres_problem, &summary);

  report.converged = summary.termination_type == ceres::CONVERGENCE;
  report.aborted = summary.termination_type == ceres::USER_FAILURE;
  report.iterations = static_cast<int>(summary.iterations.size());
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  if (report.aborted || !std::isfinite(summary.final_cost)) return report;
  for (auto& [id, x] : pose_params) {
    const Eigen::Vector3d r(x[0], x[1], x[2]);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (r.norm() > 1e-12) T.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(x[3], x[4], x[5]);
    problem.poses[id] = T;
  }
  if (gravity && !problem.down_map_fixed) problem.down_map = Eigen::Vector3d(down_map[0], down_map[1], down_map[2]).normalized();
  return report;
}

}  // namespace labo::slam
