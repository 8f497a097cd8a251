#include "localization/face/pnp_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace labo::face {

namespace {

bool in_front(const PnpProblem& p, const Eigen::Isometry3d& T) {
  for (Eigen::Index i = 0; i < p.points_face.cols(); ++i) {
    if ((T * p.points_face.col(i).eval()).z() <= 1e-3) return false;
  }
  return true;
}

Eigen::Isometry3d pose_from_cv(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  cv::cv2eigen(R_cv, R);
  Eigen::Vector3d t;
  cv::cv2eigen(tvec, t);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

cv::Matx33d camera_matrix(const IdealPinhole& c) { return {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1}; }

// A point's squared reprojection error (infinity behind the camera).
double squared_error(const PnpProblem& p, const Eigen::Isometry3d& T, Eigen::Index i) {
  const Eigen::Vector3d x = T * p.points_face.col(i).eval();
  return x.z() <= 1e-3 ? std::numeric_limits<double>::infinity() : (p.camera.project(x) - p.pixels.col(i)).squaredNorm();
}

// Computed point by point, no per-point buffer: this runs on every tracked frame.
PnpSolution make_solution(const PnpProblem& p, const Eigen::Isometry3d& T, double threshold_px, int iterations) {
  PnpSolution s;
  s.T_cam_face = T;
  s.iterations = iterations;
  double sum = 0;
  for (Eigen::Index i = 0; i < p.points_face.cols(); ++i) {
    const double e2 = squared_error(p, T, i);
    if (e2 <= threshold_px * threshold_px) {
      ++s.inliers;
      sum += e2;
    }
  }
  s.rms_px = s.inliers > 0 ? std::sqrt(sum / s.inliers) : std::numeric_limits<double>::infinity();
  return s;
}

Eigen::Matrix3d so3_exp(const Eigen::Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

}  // namespace

double reprojection_rms(const PnpProblem& problem, const Eigen::Isometry3d& T_cam_face) {
  const Eigen::Index n = problem.points_face.cols();
  if (n == 0) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i) sum += squared_error(problem, T_cam_face, i);
  return std::sqrt(sum / static_cast<double>(n));
}

std::optional<PnpSolution> solve_epnp(const PnpProblem& problem) {
  const int n = static_cast<int>(problem.points_face.cols());
  if (n < 4) return std::nullopt;
  std::vector<cv::Point3d> obj(static_cast<std::size_t>(n));
  std::vector<cv::Point2d> img(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    obj[static_cast<std::size_t>(i)] = {problem.points_face(0, i), problem.points_face(1, i), problem.points_face(2, i)};
    img[static_cast<std::size_t>(i)] = {problem.pixels(0, i), problem.pixels(1, i)};
  }
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(obj, img, camera_matrix(problem.camera), cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_EPNP)) {
    return std::nullopt;
  }
  const Eigen::Isometry3d T = pose_from_cv(rvec, tvec);
  if (!T.matrix().allFinite() || !in_front(problem, T)) return std::nullopt;
  return make_solution(problem, T, std::numeric_limits<double>::infinity(), 1);
}

std::optional<PnpSolution> solve_ransac_p3p(const PnpProblem& problem, const RansacOptions& options,
                                            std::mt19937& rng) {
  const int n = static_cast<int>(problem.points_face.cols());
  if (n < 4) return std::nullopt;
  const cv::Matx33d K = camera_matrix(problem.camera);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::optional<PnpSolution> best;
  int needed = options.max_hypotheses;
  std::vector<cv::Point3d> obj(3);
  std::vector<cv::Point2d> img(3);
  std::vector<cv::Mat> rvecs, tvecs;
  int hypothesis = 0;
  for (; hypothesis < needed; ++hypothesis) {
    int idx[3] = {pick(rng), pick(rng), pick(rng)};
    if (idx[0] == idx[1] || idx[0] == idx[2] || idx[1] == idx[2]) continue;
    for (int k = 0; k < 3; ++k) {
      const int i = idx[k];
      obj[static_cast<std::size_t>(k)] = {problem.points_face(0, i), problem.points_face(1, i), problem.points_face(2, i)};
      img[static_cast<std::size_t>(k)] = {problem.pixels(0, i), problem.pixels(1, i)};
    }
    rvecs.clear();
    tvecs.clear();
    const int solutions = cv::solveP3P(obj, img, K, cv::noArray(), rvecs, tvecs, cv::SOLVEPNP_P3P);
    for (int s = 0; s < solutions; ++s) {
      const Eigen::Isometry3d T = pose_from_cv(rvecs[static_cast<std::size_t>(s)], tvecs[static_cast<std::size_t>(s)]);
      if (!T.matrix().allFinite()) continue;
      PnpSolution candidate = make_solution(problem, T, options.inlier_threshold_px, 0);
      if (!best || candidate.inliers > best->inliers ||
          (candidate.inliers == best->inliers && candidate.rms_px < best->rms_px)) {
        best = std::move(candidate);
        // Adaptive stopping: hypotheses needed to draw an all-inlier sample with `confidence`.
        const double w = static_cast<double>(best->inliers) / n;
        const double p_good = w * w * w;
        if (p_good > 1 - 1e-9) {
          needed = std::min(needed, hypothesis + 1);
        } else if (p_good > 0) {
          const double k = std::log(1 - options.confidence) / std::log(1 - p_good);
          needed = std::min(needed, static_cast<int>(std::ceil(k)) + 1);
        }
      }
    }
  }
  if (!best || best->inliers < 4 || !in_front(problem, best->T_cam_face)) return std::nullopt;
  best->iterations = hypothesis;
  return best;
}

std::optional<PnpSolution> refine_lm(const PnpProblem& problem, const Eigen::Isometry3d& initial,
                                     const LmOptions& options, const std::vector<bool>& mask) {
  const Eigen::Index n = problem.points_face.cols();
  const auto used = [&](Eigen::Index i) { return mask.empty() || mask[static_cast<std::size_t>(i)]; };
  Eigen::Matrix3d R = initial.linear();
  Eigen::Vector3d t = initial.translation();
  const IdealPinhole& c = problem.camera;

  // Robust cost and normal equations at (R, t); false when a used point is behind the camera.
  const auto evaluate = [&](const Eigen::Matrix3d& Rc, const Eigen::Vector3d& tc, double& cost,
                            Eigen::Matrix<double, 6, 6>* H, Eigen::Matrix<double, 6, 1>* g) {
    cost = 0;
    if (H) H->setZero();
    if (g) g->setZero();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!used(i)) continue;
      const Eigen::Vector3d rp = Rc * problem.points_face.col(i);
      const Eigen::Vector3d x = rp + tc;
      if (x.z() <= 1e-3) return false;
      const double iz = 1.0 / x.z();
      const Eigen::Vector2d r = Eigen::Vector2d(c.fx * x.x() * iz + c.cx, c.fy * x.y() * iz + c.cy) - problem.pixels.col(i);
      const double e = r.norm();
      const double confidence = problem.weights.size() == n ? problem.weights(i) : 1.0;
      const double w = confidence * (e <= options.huber_px ? 1.0 : options.huber_px / e);  // Huber (IRLS weight)
      cost += confidence * (e <= options.huber_px ? 0.5 * e * e : options.huber_px * (e - 0.5 * options.huber_px));
      if (!H) continue;
      Eigen::Matrix<double, 2, 3> dpi;
      dpi << c.fx * iz, 0, -c.fx * x.x() * iz * iz, 0, c.fy * iz, -c.fy * x.y() * iz * iz;
      Eigen::Matrix<double, 3, 6> dx;  // d x / d[δθ (left), δt]
      dx.leftCols<3>() << 0, rp.z(), -rp.y(), -rp.z(), 0, rp.x(), rp.y(), -rp.x(), 0;
      dx.rightCols<3>().setIdentity();
      const Eigen::Matrix<double, 2, 6> J = dpi * dx;
      *H += w * J.transpose() * J;
      *g += w * J.transpose() * r;
    }
    return true;
  };

  double cost = 0;
  Eigen::Matrix<double, 6, 6> H;
  Eigen::Matrix<double, 6, 1> g;
  if (!evaluate(R, t, cost, &H, &g)) return std::nullopt;
  double lambda = 1e-3;
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    bool improved = false;
    for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
      Eigen::Matrix<double, 6, 6> A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
      const Eigen::Matrix<double, 6, 1> step = -A.ldlt().solve(g);
      if (!step.allFinite()) return std::nullopt;
      const Eigen::Matrix3d R_new = so3_exp(step.head<3>()) * R;
      const Eigen::Vector3d t_new = t + step.tail<3>();
      double new_cost = 0;
      if (evaluate(R_new, t_new, new_cost, nullptr, nullptr) && new_cost <= cost) {
        R = R_new;
        t = t_new;
        lambda = std::max(lambda * 0.1, 1e-9);
        improved = true;
        const bool converged = step.norm() < options.step_tolerance;
        evaluate(R, t, cost, &H, &g);
        if (converged) iteration = options.max_iterations;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Re-orthonormalise: the multiplicative updates accumulate rounding.
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = t;
  if (!in_front(problem, T)) return std::nullopt;
  PnpSolution s = make_solution(problem, T, std::numeric_limits<double>::infinity(), std::min(iteration, options.max_iterations));
  if (!mask.empty()) s.inliers = static_cast<int>(std::count(mask.begin(), mask.end(), true));
  return s;
}

}  // namespace labo::face
