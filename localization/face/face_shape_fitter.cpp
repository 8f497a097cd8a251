#include "localization/face/face_shape_fitter.hpp"

#include <algorithm>
#include <stdexcept>

namespace labo::face {

namespace {

PnpSolution fit_pose(const PnpProblem& problem, const Eigen::Isometry3d* previous) {
  LmOptions lm;
  lm.max_iterations = 30;
  if (previous) {
    if (auto r = refine_lm(problem, *previous, lm)) return *r;
  }
  auto init = solve_epnp(problem);
  if (!init) throw std::runtime_error("shape fit: no pose in front of the camera fits the landmarks");
  auto refined = refine_lm(problem, init->T_cam_face, lm);
  if (!refined) throw std::runtime_error("shape fit: pose refinement left the face behind the camera");
  return *refined;
}

// One Gauss-Newton step on the fitted shape units with the pose and the metric scale held.
void shape_step(const FaceLandmarkModel& model, const Eigen::Matrix2Xd& pixels, const IdealPinhole& cam,
                const Eigen::Isometry3d& T, double metres_per_unit, const std::vector<int>& units,
                const ShapeFitOptions& options, Eigen::VectorXd& tau) {
  const auto n = static_cast<Eigen::Index>(model.size());
  const auto k = static_cast<Eigen::Index>(units.size());
  const Eigen::Matrix3Xd points = model.points_units(tau) * metres_per_unit;
  Eigen::MatrixXd J(2 * n, k);
  Eigen::VectorXd r(2 * n);
  const Eigen::Matrix3d R = T.linear();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d x = T * points.col(i).eval();
    const double iz = 1.0 / x.z();
    r.segment<2>(2 * i) = cam.project(x) - pixels.col(i);
    Eigen::Matrix<double, 2, 3> dpi;
    dpi << cam.fx * iz, 0, -cam.fx * x.x() * iz * iz, 0, cam.fy * iz, -cam.fy * x.y() * iz * iz;
    for (Eigen::Index j = 0; j < k; ++j) {
      const Eigen::Vector3d dX = model.shape_basis().block(3 * i, units[static_cast<std::size_t>(j)], 3, 1) * metres_per_unit;
      J.block(2 * i, j, 2, 1) = dpi * R * dX;
    }
  }
  const double w = 1.0 / (options.landmark_sigma_px * options.landmark_sigma_px);
  Eigen::VectorXd tau_sub(k);
  for (Eigen::Index j = 0; j < k; ++j) tau_sub(j) = tau(units[static_cast<std::size_t>(j)]);
  Eigen::MatrixXd A = w * J.transpose() * J;
  A.diagonal().array() += options.regularisation;
  const Eigen::VectorXd b = -(w * J.transpose() * r + options.regularisation * tau_sub);
  const Eigen::VectorXd delta = A.ldlt().solve(b);
  for (Eigen::Index j = 0; j < k; ++j) {
    double& v = tau(units[static_cast<std::size_t>(j)]);
    v = std::clamp(v + delta(j), -options.bound, options.bound);
  }
}

}  // namespace

ShapeFit fit_shape(const FaceLandmarkModel& model, const Eigen::Matrix2Xd& pixels, const IdealPinhole& camera,
                   double interpupillary_distance_m, const ShapeFitOptions& options) {
  if (pixels.cols() != model.size()) {
    throw std::invalid_argument("shape fit: " + std::to_string(pixels.cols()) + " landmarks, the model has " +
                                std::to_string(model.size()));
  }
  if (!(interpupillary_distance_m > 0)) throw std::invalid_argument("shape fit: interpupillary distance must be > 0");
  ShapeFit fit;
  fit.fitted_units = model.observable_units();
  std::vector<int> units;
  for (std::size_t u = 0; u < fit.fitted_units.size(); ++u) {
    if (fit.fitted_units[u]) units.push_back(static_cast<int>(u));
  }
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.shape_unit_count());
  PnpProblem problem{model.points_m(tau, interpupillary_distance_m), pixels, camera, {}};
  PnpSolution pose = fit_pose(problem, nullptr);
  fit.rms_px_mean_shape = pose.rms_px;
  for (int a = 0; a < options.alternations; ++a) {
    const double mpu = model.metres_per_unit(tau, interpupillary_distance_m);
    for (int s = 0; s < options.gauss_newton_steps; ++s) {
      shape_step(model, pixels, camera, pose.T_cam_face, mpu, units, options, tau);
    }
    problem.points_face = model.points_m(tau, interpupillary_distance_m);
    pose = fit_pose(problem, &pose.T_cam_face);
  }
  fit.shape_params = tau;
  fit.T_cam_face = pose.T_cam_face;
  fit.rms_px = pose.rms_px;
  return fit;
}

}  // namespace labo::face
