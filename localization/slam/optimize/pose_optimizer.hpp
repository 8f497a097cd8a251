#pragma once
// Motion-only pose update: iteratively reweighted Gauss-Newton on the reprojection error in ideal
// pixels, Huber weights, noise sigma = scale^level; after each round, observations beyond the 95%
// chi-square gate (2 dof) are set aside and the pose is solved again from the rest.
// With a gravity prior the IMU's measured "down" direction in the camera adds a weighted residual on
// the camera's roll and pitch (not its yaw, not its position): in front of one plane a pitch and a
// vertical translation move the image alike, and the prior keeps the pitch from taking the blame.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"

namespace labo::slam {

struct PoseObservation {
  Eigen::Vector3d p_map;
  Eigen::Vector2d px;   // ideal pixel
  double sigma = 1.0;   // pixels
  bool inlier = true;   // output
};

// The gravity direction twice: in the map (the map's estimate) and in the camera (the IMU's roll and
// pitch at the frame), with the IMU's accuracy. Residual: R_cam_map * down_map - down_cam, / sigma.
struct GravityPrior {
  Eigen::Vector3d down_map = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d down_cam = Eigen::Vector3d::UnitY();
  double sigma_rad = 0.01;
};

struct PoseOptimizerSettings {
  int rounds = 3;
  int iterations = 10;          // per round
  double huber_px = 2.447;      // sqrt(5.991), in units of sigma
  double chi2_gate = 5.991;
};

// Refines T_cam_map in place; returns the number of inliers.
int optimize_pose(const IdealCamera& camera, std::vector<PoseObservation>& observations,
                  Eigen::Isometry3d& T_cam_map, const PoseOptimizerSettings& settings = {},
                  const std::optional<GravityPrior>& gravity = std::nullopt);

}  // namespace labo::slam
