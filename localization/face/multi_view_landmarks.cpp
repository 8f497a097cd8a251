#include "localization/face/multi_view_landmarks.hpp"

#include <array>
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::face {

namespace {

constexpr int kRightEyeFirstId = 36;  // iBUG 36-41: the subject's right eye
constexpr int kLeftEyeFirstId = 42;   // iBUG 42-47

Eigen::Vector3d eye_centre(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points, int first_id) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int id = first_id; id < first_id + 6; ++id) c += points.col(model.column_of(id));
  return c / 6.0;
}

double interpupillary_m(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points) {
  return (eye_centre(model, points, kLeftEyeFirstId) - eye_centre(model, points, kRightEyeFirstId)).norm();
}

double rms_over_views(const Eigen::Matrix3Xd& points, const std::vector<LandmarkView>& views,
                      const std::vector<Eigen::Isometry3d>& poses, const IdealPinhole& camera) {
  double sum = 0;
  long count = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (Eigen::Index j = 0; j < points.cols(); ++j) {
      const Eigen::Vector3d p = poses[v] * points.col(j);
      if (p.z() <= 0) continue;
      sum += (camera.project(p) - views[v].pixels.col(j)).squaredNorm();
      ++count;
    }
  }
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

// A landmark's reprojection in one view; pose = angle-axis and translation (face to camera).
struct LandmarkReprojection {
  LandmarkReprojection(const Eigen::Vector2d& px, const IdealPinhole& camera, double sigma_px)
      : u(px.x()), v(px.y()), fx(camera.fx), fy(camera.fy), cx(camera.cx), cy(camera.cy), inv_sigma(1.0 / sigma_px) {}
  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    for (int k = 0; k < 3; ++k) p[k] += pose[3 + k];
    if (p[2] < T(1e-6)) return false;  // behind the camera: the step is rejected
    residual[0] = (T(fx) * p[0] / p[2] + T(cx) - T(u)) * T(inv_sigma);
    residual[1] = (T(fy) * p[1] / p[2] + T(cy) - T(v)) * T(inv_sigma);
    return true;
  }
  double u, v, fx, fy, cx, cy, inv_sigma;
};

// The prior of one landmark towards its registered position, tight in the face's plane, loose in depth.
struct LandmarkPrior {
  LandmarkPrior(const Eigen::Vector3d& prior, double sigma_plane_m, double sigma_depth_m)
      : x0(prior), inv_plane(1.0 / sigma_plane_m), inv_depth(1.0 / sigma_depth_m) {}
  template <typename T>
  bool operator()(const T* point, T* residual) const {
    residual[0] = (point[0] - T(x0.x())) * T(inv_plane);
    residual[1] = (point[1] - T(x0.y())) * T(inv_plane);
    residual[2] = (point[2] - T(x0.z())) * T(inv_depth);
    return true;
  }
  Eigen::Vector3d x0;
  double inv_plane, inv_depth;
};

using Pose6 = std::array<double, 6>;

Pose6 to_params(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.linear());
  const Eigen::Vector3d r = aa.angle() * aa.axis();
  return {r.x(), r.y(), r.z(), T.translation().x(), T.translation().y(), T.translation().z()};
}

Eigen::Isometry3d from_params(const Pose6& x) {
  const Eigen::Vector3d r(x[0], x[1], x[2]);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (r.norm() > 1e-12) T.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x[3], x[4], x[5]);
  return T;
}

// Poses and points together (Levenberg-Marquardt, Schur complement on the points): alternating the
// two converges very slowly along the directions that couple them (a landmark's depth against the
// views' pitch), which are the ones this refinement is for.
void adjust_jointly(MultiViewFit& fit, const Eigen::Matrix3Xd& prior, const std::vector<LandmarkView>& views,
                    const IdealPinhole& camera, const MultiViewOptions& options) {
  std::vector<Pose6> poses;
  poses.reserve(fit.poses.size());
  for (const auto& T : fit.poses) poses.push_back(to_params(T));
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::HuberLoss huber(options.huber_px / options.pixel_sigma_px);  // residuals are in sigmas
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (Eigen::Index j = 0; j < fit.points_m.cols(); ++j) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LandmarkReprojection, 2, 6, 3>(
                                   new LandmarkReprojection(views[v].pixels.col(j), camera, options.pixel_sigma_px)),
                               &huber, poses[v].data(), fit.points_m.col(j).data());
    }
  }
  for (Eigen::Index j = 0; j < fit.points_m.cols(); ++j) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LandmarkPrior, 3, 3>(new LandmarkPrior(
                                 prior.col(j), options.prior_sigma_m, options.prior_depth_sigma_m)),
                             nullptr, fit.points_m.col(j).data());
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;  // deterministic
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  for (std::size_t v = 0; v < poses.size(); ++v) fit.poses[v] = from_params(poses[v]);
}

void check_inputs(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& model_points_m,
                  const std::vector<LandmarkView>& views, double interpupillary_distance_m) {
  if (model_points_m.cols() != model.size()) {
    throw std::invalid_argument("multi-view landmarks: " + std::to_string(model_points_m.cols()) +
                                " model points, expected the model's " + std::to_string(model.size()));
  }
  if (views.size() < 3) {
    throw std::invalid_argument("multi-view landmarks: " + std::to_string(views.size()) +
                                " views, expected at least 3");
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (views[v].pixels.cols() != model.size()) {
      throw std::invalid_argument("multi-view landmarks: view " + std::to_string(v) + " has " +
                                  std::to_string(views[v].pixels.cols()) + " landmarks, expected " +
                                  std::to_string(model.size()));
    }
  }
  if (!(interpupillary_distance_m > 0)) throw std::invalid_argument("multi-view landmarks: IPD must be positive");
}

}  // namespace

MultiViewFit refine_landmarks_from_views(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& model_points_m,
                                         const std::vector<LandmarkView>& views, const IdealPinhole& camera,
                                         double interpupillary_distance_m, const MultiViewOptions& options) {
  check_inputs(model, model_points_m, views, interpupillary_distance_m);
  MultiViewFit fit;
  fit.points_m = model_points_m;
  fit.poses.reserve(views.size());
  for (const auto& v : views) fit.poses.push_back(v.T_cam_face_initial);

  PnpProblem problem;
  problem.camera = camera;
  LmOptions lm;
  lm.huber_px = options.huber_px;
  const auto refine_poses = [&] {
    problem.points_face = fit.points_m;
    for (std::size_t v = 0; v < views.size(); ++v) {
      problem.pixels = views[v].pixels;
      if (const auto s = refine_lm(problem, fit.poses[v], lm)) fit.poses[v] = s->T_cam_face;
    }
  };
  refine_poses();  // the initial poses may be another model's (the tracker's): start consistent
  fit.rms_before_px = rms_over_views(fit.points_m, views, fit.poses, camera);
  adjust_jointly(fit, model_points_m, views, camera, options);
  // Back to the person's metric size: scaling the points and the poses' translations together does
  // not change a single image, so only the IPD can fix it.
  const double scale = interpupillary_distance_m / interpupillary_m(model, fit.points_m);
  fit.points_m *= scale;
  for (auto& T : fit.poses) T.translation() *= scale;
  fit.rms_after_px = rms_over_views(fit.points_m, views, fit.poses, camera);
  return fit;
}

}  // namespace labo::face
