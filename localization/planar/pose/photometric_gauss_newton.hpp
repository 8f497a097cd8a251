#pragma once
// The Gauss-Newton machinery the two photometric pose refiners share: Se3PoseRefiner (template samples
// read in the smoothed, undistorted frame) and AreaPoseRefiner (raw frame pixels predicted as the
// template's mean over their footprint). Both fit the same 11 parameters — the pose's left increment
// exp(xi) T, then the panel's appearance (gain affine across the panel, bias, the frame's extra blur) —
// and differ only in how a residual and its Jacobian row are formed; each supplies that as its
// `accumulate` (T, appearance) -> PhotometricNormal. Here: the normal equations, the iteration and its
// stop rules, the step, and the covariance of the result.
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "localization/planar/pose/se3_pose_refiner.hpp"

namespace labo::planar {

// Pose (rotation vector, translation), gain, its gradients across the panel (x, y), bias, blur.
constexpr int kPhotometricParams = 11;
constexpr int kPhotometricBlurParam = 10;
using PhotometricVector = Eigen::Matrix<double, kPhotometricParams, 1>;
using PhotometricMatrix = Eigen::Matrix<double, kPhotometricParams, kPhotometricParams>;

struct PhotometricNormal {
  PhotometricMatrix JtJ = PhotometricMatrix::Zero();
  PhotometricVector Jtr = PhotometricVector::Zero();
  double ssr = 0;  // sum of squared residuals
  int valid = 0;   // residuals summed
  double sum_grey = 0, sum_grey2 = 0;  // of the frame's grey levels fitted: how much of their variance the fit explains
};

// Grey level = (gain + gain_x x + gain_y y) (prediction + blur * its change with blur) + bias, x and y
// across the panel in [-1, 1]: brightness, contrast, a light gradient, and the frame's blur beyond the
// model's (each refiner says in which unit).
struct PanelAppearance {
  double gain = 1, gain_x = 0, gain_y = 0, bias = 0, blur = 0;
};

// How a step is judged: by the sum of squared residuals (a fixed set of template samples) or by their
// mean (frame pixels near the panel's edge may leave or join the fit as the pose moves).
enum class ResidualComparison { Sum, Mean };

struct GaussNewtonRun {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  PanelAppearance appearance;
  PhotometricNormal normal;  // at T (the last point evaluated within convergence_px of it)
  int iterations = 0;
  const char* failure = "";  // non-empty: no usable result
};

// The largest image motion (px) of the panel's four corners between poses a and b.
double max_corner_shift_px(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double width_m, double height_m,
                           double fx, double fy);

// Gauss-Newton from `T_begin`: each iteration evaluates `accumulate(T, appearance)`; a step that raises
// the residual (as `comparison` says) is undone and ends the run; the run also ends when no corner
// moves more than `convergence_px`. Fails when fewer than `needed` residuals were summed or the
// normal equations are singular. Allocates nothing.
template <typename Accumulate>
GaussNewtonRun run_gauss_newton(const Eigen::Isometry3d& T_begin, Accumulate&& accumulate, int needed,
                                ResidualComparison comparison, int max_iterations, double convergence_px, double width_m,
                                double height_m, double fx, double fy) {
  GaussNewtonRun run;
  Eigen::Isometry3d T = T_begin, T_previous = T;
  PanelAppearance& a = run.appearance;
  PhotometricNormal n, n_previous;
  const auto worse = [&] {
    return comparison == ResidualComparison::Sum ? n.ssr > n_previous.ssr
                                                 : n.ssr / n.valid > n_previous.ssr / n_previous.valid;
  };
  for (int it = 0; it < max_iterations; ++it) {
    n = accumulate(T, static_cast<const PanelAppearance&>(a));
    ++run.iterations;
    if (n.valid < needed) {
      run.failure = "too little of the panel in view";
      return run;
    }
    if (it > 0 && worse()) {  // the last step made it worse: undo it and stop
      T = T_previous;
      n = n_previous;
      break;
    }
    const PhotometricVector delta = -n.JtJ.ldlt().solve(n.Jtr);
    if (!delta.allFinite()) {
      run.failure = "singular normal equations";
      return run;
    }
    T_previous = T;
    n_previous = n;
    const Eigen::Vector3d omega = delta.head<3>();
    const double angle = omega.norm();
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    if (angle > 0) step.linear() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
    step.translation() = delta.segment<3>(3);
    T = step * T;
    a.gain += delta[6];
    a.gain_x += delta[7];
    a.gain_y += delta[8];
    a.bias += delta[9];
    a.blur += delta[kPhotometricBlurParam];
    if (max_corner_shift_px(T, T_previous, width_m, height_m, fx, fy) < convergence_px) break;
  }
  run.T = T;
  run.normal = n;
  return run;
}

// The run's result into `out` (whose T_cam_object is the starting pose): refused (out.failure says why,
// out.refined stays false) when the run failed, the gain collapsed, the fit explains the frame's grey
// levels with a correlation below settings.min_correlation, or a corner of the panel ended more than
// `leash_px` from where T_start puts it. Otherwise the pose, the RMS residual and the Gauss-Newton
// covariance sigma^2 (J^T J)^-1 of the pose, marginalized over the appearance, with sigma^2 the residual
// variance, inflated by settings.covariance_inflation, plus the rotation floor, and the worst-axis
// sigmas. Leaves `blur_variance_px2` to the caller (its unit is the refiner's). Returns out.refined.
// The leash is measured over the part of the panel in view at T_start (a 5 x 5 grid of its points
// inside `image` of the undistorted frame, whose principal point is (cx, cy)): beyond the image's edge
// the tracker's homography is an extrapolation, and a partly visible panel's far corners may
// legitimately move farther.
bool finish_refinement(const GaussNewtonRun& run, const Eigen::Isometry3d& T_start, double leash_px, double width_m,
                       double height_m, double fx, double fy, double cx, double cy, cv::Size image,
                       const Se3RefinerSettings& settings, Se3Refinement& out);

}  // namespace labo::planar
