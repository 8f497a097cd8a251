#include "localization/face/depth_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "localization/face/face_geometry.hpp"

namespace labo::face {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// iBUG-68 regions of the rigid subset, each with its own depth offset component.
struct Region {
  int first, last;
};
constexpr Region kRegions[] = {{17, 26}, {27, 30}, {31, 35}, {36, 47}, {48, 59}};  // brows, bridge, nose base, eyes, mouth

std::string fixed(double v, int decimals) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

// Removes from `v` its part in the span of the orthonormal columns of `q` (those set so far).
void orthogonalise(Eigen::VectorXd& v, const Eigen::MatrixXd& q, Eigen::Index columns) {
  for (int pass = 0; pass < 2; ++pass) {  // twice: Gram-Schmidt loses orthogonality once
    for (Eigen::Index c = 0; c < columns; ++c) v -= q.col(c).dot(v) * q.col(c);
  }
}

// The face's pose and the depth coefficients that explain the views, by Levenberg-Marquardt with the
// poses eliminated per view (Schur complement: each pose couples only with the few coefficients).
class DepthAdjustment {
 public:
  // `components` (n x k) with the inverse prior variance of each coefficient (k).
  DepthAdjustment(const Eigen::Matrix3Xd& points, const Eigen::MatrixXd& components, const Eigen::VectorXd& prior_weights,
                  const std::vector<DepthView>& views, const IdealPinhole& camera, const DepthRefinementOptions& options)
      : base_(points), B_(components), prior_(prior_weights), views_(views), cam_(camera), options_(options) {}

  // Points for coefficients c.
  Eigen::Matrix3Xd points(const Eigen::VectorXd& c) const {
    Eigen::Matrix3Xd p = base_;
    p.row(2) += (B_ * c).transpose();
    return p;
  }

  // Robust cost (in squared sigmas) of the views and the prior; infinity when a point is behind the camera.
  double cost(const std::vector<Eigen::Isometry3d>& poses, const Eigen::VectorXd& c) const {
    const Eigen::Matrix3Xd p = points(c);
    double sum = c.dot(prior_.cwiseProduct(c));
    const double inv_var = 1.0 / (options_.pixel_sigma_px * options_.pixel_sigma_px);
    for (std::size_t v = 0; v < views_.size(); ++v) {
      for (Eigen::Index i = 0; i < p.cols(); ++i) {
        const Eigen::Vector3d x = poses[v] * p.col(i).eval();
        if (!(x.z() > 1e-6)) return std::numeric_limits<double>::infinity();
        const double e = (cam_.project(x) - views_[v].pixels.col(i)).norm();
        const double h = options_.huber_px;
        sum += inv_var * (e <= h ? e * e : 2 * h * e - h * h);
      }
    }
    return sum;
  }

  // One damped Gauss-Newton step from (poses, c) with damping `lambda`; false when a pose block is singular.
  bool step(const std::vector<Eigen::Isometry3d>& poses, const Eigen::VectorXd& c, double lambda,
            std::vector<Eigen::Isometry3d>& new_poses, Eigen::VectorXd& new_c) const {
    const Eigen::Index k = B_.cols();
    const Eigen::Matrix3Xd p = points(c);
    const double inv_var = 1.0 / (options_.pixel_sigma_px * options_.pixel_sigma_px);
    Eigen::MatrixXd S = prior_.asDiagonal();
    Eigen::VectorXd b = prior_.cwiseProduct(c);
    std::vector<Eigen::Matrix<double, 6, 6>> Hpp_inv(views_.size());
    std::vector<Eigen::MatrixXd> Hpc(views_.size());
    std::vector<Eigen::Matrix<double, 6, 1>> gp(views_.size());
    Eigen::MatrixXd Jc(2, k);
    for (std::size_t v = 0; v < views_.size(); ++v) {
      Eigen::Matrix<double, 6, 6> Hpp = Eigen::Matrix<double, 6, 6>::Zero();
      Hpc[v] = Eigen::MatrixXd::Zero(6, k);
      gp[v].setZero();
      const Eigen::Matrix3d R = poses[v].linear();
      const Eigen::Vector3d depth_dir = R.col(2);
      for (Eigen::Index i = 0; i < p.cols(); ++i) {
        const Eigen::Vector3d Rp = R * p.col(i);
        const Eigen::Vector3d x = Rp + poses[v].translation();
        const double iz = 1.0 / x.z();
        const Eigen::Vector2d r = cam_.project(x) - views_[v].pixels.col(i);
        Eigen::Matrix<double, 2, 3> dpi;
        dpi << cam_.fx * iz, 0, -cam_.fx * x.x() * iz * iz, 0, cam_.fy * iz, -cam_.fy * x.y() * iz * iz;
        Eigen::Matrix<double, 3, 6> dx_dpose;
        dx_dpose << 0, Rp.z(), -Rp.y(), 1, 0, 0,  //
            -Rp.z(), 0, Rp.x(), 0, 1, 0,           //
            Rp.y(), -Rp.x(), 0, 0, 0, 1;           // d(x)/d(ω, t) for x = (I + [ω]x) R p + t + δt
        const Eigen::Matrix<double, 2, 6> Jp = dpi * dx_dpose;
        Jc = (dpi * depth_dir) * B_.row(i);
        const double e = r.norm();
        const double w = inv_var * (e <= options_.huber_px ? 1.0 : options_.huber_px / e);  // IRLS Huber
        Hpp += w * Jp.transpose() * Jp;
        Hpc[v] += w * Jp.transpose() * Jc;
        gp[v] += w * Jp.transpose() * r;
        S += w * Jc.transpose() * Jc;
        b += w * Jc.transpose() * r;
      }
      Hpp.diagonal() *= 1.0 + lambda;
      const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(Hpp);
      if (!lu.isInvertible()) return false;
      Hpp_inv[v] = lu.inverse();
      S -= Hpc[v].transpose() * Hpp_inv[v] * Hpc[v];
      b -= Hpc[v].transpose() * Hpp_inv[v] * gp[v];
    }
    S.diagonal() *= 1.0 + lambda;
    const Eigen::VectorXd dc = S.ldlt().solve(-b);
    if (!dc.allFinite()) return false;
    new_c = c + dc;
    new_poses.resize(poses.size());
    for (std::size_t v = 0; v < views_.size(); ++v) {
      const Eigen::Matrix<double, 6, 1> d = -Hpp_inv[v] * (gp[v] + Hpc[v] * dc);
      const Eigen::Vector3d w = d.head<3>();
      Eigen::Isometry3d T = poses[v];
      if (w.norm() > 1e-15) T.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * T.linear();
      T.translation() += d.tail<3>();
      new_poses[v] = T;
    }
    return true;
  }

 private:
  const Eigen::Matrix3Xd& base_;
  const Eigen::MatrixXd& B_;
  const Eigen::VectorXd& prior_;
  const std::vector<DepthView>& views_;
  IdealPinhole cam_;
  DepthRefinementOptions options_;
};

double rms_over_views(const Eigen::Matrix3Xd& points, const std::vector<DepthView>& views,
                      const std::vector<Eigen::Isometry3d>& poses, const IdealPinhole& camera) {
  double sum = 0;
  long count = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (Eigen::Index j = 0; j < points.cols(); ++j) {
      const Eigen::Vector3d p = poses[v] * points.col(j).eval();
      if (!(p.z() > 0)) return std::numeric_limits<double>::infinity();
      sum += (camera.project(p) - views[v].pixels.col(j)).squaredNorm();
      ++count;
    }
  }
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

// The views' own poses for the registered points first (the given ones may be another model's).
std::vector<Eigen::Isometry3d> consistent_poses(const Eigen::Matrix3Xd& points, const std::vector<DepthView>& views,
                                                const IdealPinhole& camera, const DepthRefinementOptions& options) {
  std::vector<Eigen::Isometry3d> poses;
  PnpProblem problem{points, {}, camera, {}};
  LmOptions lm;
  lm.huber_px = options.huber_px;
  for (const auto& v : views) {
    problem.pixels = v.pixels;
    const auto s = refine_lm(problem, v.T_cam_face_initial, lm);
    poses.push_back(s ? s->T_cam_face : v.T_cam_face_initial);
  }
  return poses;
}

// Why the views cannot refine a shape, or "" when they can.
std::string spread_refusal(const std::vector<DepthView>& views, const DepthRefinementOptions& options,
                           DepthRefinement& out) {
  if (static_cast<int>(views.size()) < options.min_views) {
    return "refinement refused: " + std::to_string(views.size()) + " views, expected at least " +
           std::to_string(options.min_views);
  }
  double yaw_min = 1e9, yaw_max = -1e9, pitch_min = 1e9, pitch_max = -1e9;
  for (const auto& v : views) {
    const HeadAngles a = head_angles(v.T_cam_face_initial.linear());
    yaw_min = std::min(yaw_min, a.yaw);
    yaw_max = std::max(yaw_max, a.yaw);
    pitch_min = std::min(pitch_min, a.pitch);
    pitch_max = std::max(pitch_max, a.pitch);
  }
  out.yaw_span_rad = yaw_max - yaw_min;
  out.pitch_span_rad = pitch_max - pitch_min;
  if (out.yaw_span_rad < options.min_yaw_span_rad || out.pitch_span_rad < options.min_pitch_span_rad) {
    return "refinement refused: the views span " + fixed(out.yaw_span_rad * kDeg, 1) + "° of yaw and " +
           fixed(out.pitch_span_rad * kDeg, 1) + "° of pitch, expected at least " +
           fixed(options.min_yaw_span_rad * kDeg, 1) + "° and " + fixed(options.min_pitch_span_rad * kDeg, 1) +
           "° (the head turned left, right, up and down)";
  }
  return {};
}

void check_sizes(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points, const std::vector<DepthView>& views) {
  if (points.cols() != model.size()) {
    throw std::invalid_argument("depth refinement: " + std::to_string(points.cols()) + " points, expected the model's " +
                                std::to_string(model.size()));
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (views[v].pixels.cols() != model.size()) {
      throw std::invalid_argument("depth refinement: view " + std::to_string(v) + " has " +
                                  std::to_string(views[v].pixels.cols()) + " landmarks, expected " +
                                  std::to_string(model.size()));
    }
  }
}

}  // namespace

Eigen::MatrixXd depth_components(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points_m) {
  const Eigen::Index n = points_m.cols();
  const double root_n = std::sqrt(static_cast<double>(n));
  // The gauge span {1, x, y}, orthonormalised, then the components after it.
  Eigen::MatrixXd q(n, 3 + 1 + static_cast<Eigen::Index>(std::size(kRegions)));
  Eigen::Index columns = 0;
  const auto add = [&](Eigen::VectorXd v) {
    const double before = v.norm();
    orthogonalise(v, q, columns);
    if (before <= 0 || v.norm() < 0.05 * before) return;  // nothing left beyond the span so far
    q.col(columns++) = v.normalized();
  };
  add(Eigen::VectorXd::Ones(n));
  add(points_m.row(0).transpose());
  add(points_m.row(1).transpose());
  const Eigen::Index gauge = columns;
  add(points_m.row(2).transpose());  // the depth profile: a gain
  for (const Region& region : kRegions) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    for (int id = region.first; id <= region.last; ++id) {
      if (const int c = model.column_of(id); c >= 0) v(c) = 1;
    }
    add(v);
  }
  return q.middleCols(gauge, columns - gauge) * root_n;  // RMS 1 over the landmarks
}

DepthRefinement refine_depth_from_views(const FaceLandmarkModel& model, const Eigen::Matrix3Xd& points_m,
                                        const std::vector<DepthView>& views, const IdealPinhole& camera,
                                        const DepthRefinementOptions& options) {
  check_sizes(model, points_m, views);
  DepthRefinement out;
  out.views = static_cast<int>(views.size());
  out.depth_change_m = Eigen::VectorXd::Zero(points_m.cols());
  const Eigen::MatrixXd components = depth_components(model, points_m);
  const Eigen::Index n = points_m.cols(), k = components.cols();
  const bool per_landmark = options.landmark_prior_sigma_m > 0;
  Eigen::MatrixXd B(n, k + (per_landmark ? n : 0));
  Eigen::VectorXd prior(B.cols());
  B.leftCols(k) = components;
  prior.head(k).setConstant(1.0 / (options.prior_sigma_m * options.prior_sigma_m));
  if (per_landmark) {
    // Each landmark's depth less its part along the gauge {1, x, y} (least squares over the landmarks).
    Eigen::MatrixXd G(n, 3);
    G << Eigen::VectorXd::Ones(n), points_m.row(0).transpose(), points_m.row(1).transpose();
    B.rightCols(n) = Eigen::MatrixXd::Identity(n, n) - G * (G.transpose() * G).ldlt().solve(G.transpose());
    prior.tail(n).setConstant(1.0 / (options.landmark_prior_sigma_m * options.landmark_prior_sigma_m));
  }
  out.coefficients_m = Eigen::VectorXd::Zero(B.cols());
  if (out.reason = spread_refusal(views, options, out); !out.reason.empty()) return out;

  std::vector<Eigen::Isometry3d> poses = consistent_poses(points_m, views, camera, options);
  out.rms_before_px = rms_over_views(points_m, views, poses, camera);
  const DepthAdjustment adjustment(points_m, B, prior, views, camera, options);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(B.cols());
  double cost = adjustment.cost(poses, c);
  double lambda = 1e-3;
  std::vector<Eigen::Isometry3d> trial_poses;
  Eigen::VectorXd trial_c;
  for (int it = 0; it < options.max_iterations && std::isfinite(cost); ++it) {
    out.iterations = it + 1;
    if (!adjustment.step(poses, c, lambda, trial_poses, trial_c)) break;
    const double trial_cost = adjustment.cost(trial_poses, trial_c);
    if (trial_cost < cost) {
      const bool converged = cost - trial_cost < 1e-9 * cost;
      poses = trial_poses;
      c = trial_c;
      cost = trial_cost;
      lambda = std::max(lambda * 0.3, 1e-9);
      if (converged) break;
    } else {
      lambda *= 10;
      if (lambda > 1e8) break;
    }
  }
  const Eigen::VectorXd change = B * c;
  out.rms_after_px = rms_over_views(adjustment.points(c), views, poses, camera);
  out.poses = poses;
  if (!c.allFinite() || !std::isfinite(out.rms_after_px)) {
    out.reason = "refinement refused: the fit diverged (no finite solution)";
  } else if (out.rms_after_px > options.max_rms_px) {
    out.reason = "refinement refused: the landmarks fit the refined shape to " + fixed(out.rms_after_px, 2) +
                 " px RMS, expected at most " + fixed(options.max_rms_px, 2) + " px (not one rigid face?)";
  } else if (out.rms_after_px > out.rms_before_px * 1.01) {
    out.reason = "refinement refused: the fit got worse (" + fixed(out.rms_before_px, 2) + " -> " +
                 fixed(out.rms_after_px, 2) + " px RMS)";
  } else if (change.cwiseAbs().maxCoeff() > options.max_depth_change_m) {
    out.reason = "refinement refused: a landmark's depth would change by " +
                 fixed(change.cwiseAbs().maxCoeff() * 1000.0, 1) + " mm, expected at most " +
                 fixed(options.max_depth_change_m * 1000.0, 1) + " mm";
  }
  if (!out.reason.empty()) return out;
  out.accepted = true;
  out.coefficients_m = c;
  out.depth_change_m = change;
  return out;
}

}  // namespace labo::face
