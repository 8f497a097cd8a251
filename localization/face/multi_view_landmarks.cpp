#include "localization/face/multi_view_landmarks.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace labo::face {

namespace {

constexpr int kRightEyeFirstId = 36;  // iBUG 36-41: the subject's right eye
constexpr int kLeftEyeFirstId = 42;   // iBUG 42-47
constexpr int kPointIterations = 3;   // per alternation; each point's problem is nearly linear

double huber_weight(double residual_px, double k_px) { return residual_px <= k_px ? 1.0 : k_px / residual_px; }

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

// Gauss-Newton on one landmark's 3-D point: its reprojection in every view (Huber-weighted) plus the
// prior towards its model position. The poses are held fixed, so the points are independent.
Eigen::Vector3d refine_point(Eigen::Vector3d X, const Eigen::Vector3d& prior, Eigen::Index j,
                             const std::vector<LandmarkView>& views, const std::vector<Eigen::Isometry3d>& poses,
                             const IdealPinhole& camera, const MultiViewOptions& options) {
  const Eigen::Vector3d prior_weight(1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                                     1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                                     1.0 / (options.prior_depth_sigma_m * options.prior_depth_sigma_m));
  const double pixel_weight = 1.0 / (options.pixel_sigma_px * options.pixel_sigma_px);
  for (int it = 0; it < kPointIterations; ++it) {
    Eigen::Matrix3d H = prior_weight.asDiagonal();
    Eigen::Vector3d g = prior_weight.cwiseProduct(X - prior);
    for (std::size_t v = 0; v < views.size(); ++v) {
      const Eigen::Vector3d p = poses[v] * X;
      if (p.z() <= 1e-6) continue;
      const Eigen::Vector2d r = camera.project(p) - views[v].pixels.col(j);
      const double w = pixel_weight * huber_weight(r.norm(), options.huber_px);
      const double iz = 1.0 / p.z();
      Eigen::Matrix<double, 2, 3> d_proj;
      d_proj << camera.fx * iz, 0, -camera.fx * p.x() * iz * iz, 0, camera.fy * iz, -camera.fy * p.y() * iz * iz;
      const Eigen::Matrix<double, 2, 3> J = d_proj * poses[v].linear();
      H += w * J.transpose() * J;
      g += w * J.transpose() * r;
    }
    const Eigen::Vector3d step = -H.ldlt().solve(g);
    X += step;
    if (step.norm() < 1e-8) break;
  }
  return X;
}

// The rigid motion of the points (and the opposite one of every pose, so no image changes) that best
// satisfies the prior: the alternation alone moves along that motion very slowly, because the images
// do not see it at all, so it is solved for directly (Gauss-Newton on rotation vector and shift).
void pin_gauge(MultiViewFit& fit, const Eigen::Matrix3Xd& prior, const MultiViewOptions& options) {
  const Eigen::Vector3d w(1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                          1.0 / (options.prior_sigma_m * options.prior_sigma_m),
                          1.0 / (options.prior_depth_sigma_m * options.prior_depth_sigma_m));
  for (int it = 0; it < 3; ++it) {
    const Eigen::Vector3d c = fit.points_m.rowwise().mean();
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (Eigen::Index j = 0; j < prior.cols(); ++j) {
      const Eigen::Vector3d d = fit.points_m.col(j) - c;
      Eigen::Matrix<double, 3, 6> J;
      J << 0, d.z(), -d.y(), 1, 0, 0, -d.z(), 0, d.x(), 0, 1, 0, d.y(), -d.x(), 0, 0, 0, 1;  // [-[d]x, I]
      const Eigen::Vector3d r = fit.points_m.col(j) - prior.col(j);
      H += J.transpose() * w.asDiagonal() * J;
      g += J.transpose() * w.cwiseProduct(r);
    }
    const Eigen::Matrix<double, 6, 1> step = -H.ldlt().solve(g);
    const Eigen::Vector3d omega = step.head<3>();
    const Eigen::Matrix3d Q =
        omega.norm() > 1e-12 ? Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d shift = step.tail<3>();
    fit.points_m = ((Q * (fit.points_m.colwise() - c)).colwise() + (c + shift)).eval();
    for (auto& T : fit.poses) {
      // T' (Q (X - c) + c + shift) = T X for every X.
      const Eigen::Matrix3d R = T.linear() * Q.transpose();
      T.translation() = T.translation() + T.linear() * c - R * (c + shift);
      T.linear() = R;
    }
    if (step.norm() < 1e-10) break;
  }
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
  for (int a = 0; a < options.alternations; ++a) {
    for (Eigen::Index j = 0; j < fit.points_m.cols(); ++j) {
      fit.points_m.col(j) = refine_point(fit.points_m.col(j), model_points_m.col(j), j, views, fit.poses, camera, options);
    }
    pin_gauge(fit, model_points_m, options);
    refine_poses();
  }
  // Back to the person's metric size: scaling the points and the poses' translations together does
  // not change a single image, so only the IPD can fix it.
  const double scale = interpupillary_distance_m / interpupillary_m(model, fit.points_m);
  fit.points_m *= scale;
  for (auto& T : fit.poses) T.translation() *= scale;
  fit.rms_after_px = rms_over_views(fit.points_m, views, fit.poses, camera);
  return fit;
}

}  // namespace labo::face
