#pragma once
// Motion-only pose update: iteratively reweighted Gauss-Newton on the reprojection error in ideal
// pixels, Huber weights, noise sigma = scale^level; after each round, observations beyond the 95%
// chi-square gate (2 dof) are set aside and the pose is solved again from the rest.
#include <Eigen/Geometry>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"

namespace labo::slam {

struct PoseObservation {
  Eigen::Vector3d p_map;
  Eigen::Vector2d px;   // ideal pixel
  double sigma = 1.0;   // pixels
  bool inlier = true;   // output
};

struct PoseOptimizerSettings {
  int rounds = 3;
  int iterations = 10;          // per round
  double huber_px = 2.447;      // sqrt(5.991), in units of sigma
  double chi2_gate = 5.991;
};

// Refines T_cam_map in place; returns the number of inliers.
int optimize_pose(const IdealCamera& camera, std::vector<PoseObservation>& observations,
                  Eigen::Isometry3d& T_cam_map, const PoseOptimizerSettings& settings = {});

}  // namespace labo::slam
