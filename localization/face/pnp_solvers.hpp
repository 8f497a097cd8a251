#pragma once
// Perspective-n-point solvers for the face: EPnP (closed form), RANSAC over P3P minimal solutions,
// and a robust Levenberg-Marquardt refinement of the reprojection error. All work on undistorted
// ("ideal") pixels with a distortion-free pinhole K: the front camera's distortion is removed from
// the landmarks once, before any solver runs.
#include <Eigen/Geometry>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace labo::face {

struct IdealPinhole {
  double fx = 1, fy = 1, cx = 0, cy = 0;
  Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const {
    return {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  }
};

struct PnpProblem {
  Eigen::Matrix3Xd points_face;  // 3 x n, metres, face frame
  Eigen::Matrix2Xd pixels;       // 2 x n, undistorted pixels
  IdealPinhole camera;
  // Per-point confidence for the Levenberg-Marquardt refinement (empty: all 1); the closed-form and
  // minimal solvers ignore it.
  Eigen::VectorXd weights;
};

struct PnpSolution {
  Eigen::Isometry3d T_cam_face = Eigen::Isometry3d::Identity();
  double rms_px = 0;       // over the inliers
  int inliers = 0;
  int iterations = 0;      // RANSAC hypotheses or LM iterations
};

// RMS reprojection error of all points; infinity when a point
// lies behind the camera.
double reprojection_rms(const PnpProblem& problem, const Eigen::Isometry3d& T_cam_face);

// EPnP; empty when OpenCV finds no solution or the face ends up behind the camera. n >= 4.
std::optional<PnpSolution> solve_epnp(const PnpProblem& problem);

struct RansacOptions {
  double inlier_threshold_px = 3.0;
  int max_hypotheses = 100;
  double confidence = 0.99;
};
// RANSAC over P3P minimal solutions (up to four per sample), scored by inlier count then RMS; the
// answer is the best minimal pose, unrefined (the paper's "RANSAC P3P"). Deterministic for a given
// generator state.
std::optional<PnpSolution> solve_ransac_p3p(const PnpProblem& problem, const RansacOptions& options,
                                            std::mt19937& rng);

struct LmOptions {
  int max_iterations = 20;
  double huber_px = 3.0;           // residuals beyond this are down-weighted (landmark outliers)
  double step_tolerance = 1e-7;    // stop when the update is this small (rad, m)
};
// Levenberg-Marquardt on the robust reprojection error from `initial`; uses only points whose mask
// entry is true (all when the mask is empty). Empty when the pose ends up behind the camera.
std::optional<PnpSolution> refine_lm(const PnpProblem& problem, const Eigen::Isometry3d& initial,
                                     const LmOptions& options, const std::vector<bool>& mask = {});

}  // namespace labo::face
