#pragma once
// The similarity between two parts of a monocular map that saw the same place: pairs of map points
// (a point of the current keyframe, in the drifted part; the matching point of the loop keyframe, in
// the old part) give G with old = G * current. RANSAC over minimal sets of 3 pairs (Umeyama's
// closed form with scale); a pair is an inlier when the transformed points reproject onto their
// features in both keyframes (chi-square gate in sigmas of the feature's level). The best model is
// refined on its inliers by minimising those reprojection errors (Ceres, Huber).
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/optimize/sim3.hpp"

namespace labo::slam {

struct Sim3Pair {
  Eigen::Vector3d current_point;   // map coordinates of the drifted part
  Eigen::Vector3d old_point;       // map coordinates of the old part
  Eigen::Vector2d current_px;      // where the current keyframe sees current_point (ideal pixels)
  Eigen::Vector2d old_px;          // where the loop keyframe sees old_point
  double current_sigma = 1.0, old_sigma = 1.0;
};

struct Sim3SolverSettings {
  int iterations = 300;
  double chi2_gate = 9.21;  // 99 %, 2 dof
  int min_inliers = 20;
  unsigned seed = 1;        // deterministic
};

struct Sim3Estimate {
  Similarity3 old_from_current;  // G: old = G * current
  std::vector<int> inliers;      // indices into the pairs
};

std::optional<Sim3Estimate> solve_sim3(const IdealCamera& camera, const std::vector<Sim3Pair>& pairs,
                                       const Eigen::Isometry3d& T_current_cam_map, const Eigen::Isometry3d& T_old_cam_map,
                                       const Sim3SolverSettings& settings = {});

}  // namespace labo::slam
