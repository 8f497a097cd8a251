#pragma once
// Bundle adjustment with Ceres: keyframe poses (angle-axis + translation of T_cam_map) and point
// positions, reprojection error in ideal pixels divided by sigma = scale^level, Huber loss,
// Levenberg-Marquardt. A problem is copied out of the map, solved without holding the map lock, and
// written back by the caller. `abort` (may be null) stops the solve between iterations: the mapper
// sets it when a new keyframe arrives, so adjustment never delays a keyframe. An optional gravity
// prior (the IMU's roll and pitch) holds each keyframe's tilt against the map's gravity direction.
#include <Eigen/Geometry>
#include <atomic>
#include <map>
#include <optional>
#include <vector>

#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/map/keyframe.hpp"

namespace labo::slam {

struct BundleObservation {
  int keyframe;
  PointId point;
  Eigen::Vector2d px;
  double sigma;
};

struct BundleProblem {
  std::map<int, Eigen::Isometry3d> poses;    // keyframe id -> T_cam_map
  std::map<int, bool> pose_fixed;
  std::map<PointId, Eigen::Vector3d> points;
  std::vector<BundleObservation> observations;
  // Gravity prior (used when gravity_sigma_rad > 0 and down_map is set): per keyframe the IMU's
  // "down" in its camera; residual (R_cam_map * down_map - down_cam) / sigma on each free keyframe.
  // down_map (the map's gravity direction) is estimated too unless down_map_fixed.
  std::map<int, Eigen::Vector3d> down_cam;
  std::optional<Eigen::Vector3d> down_map;
  bool down_map_fixed = true;
  double gravity_sigma_rad = 0;
};

struct BundleSettings {
  int max_iterations = 20;
  double huber_px = 2.447;  // in sigmas
};

struct BundleReport {
  bool converged = false;
  bool aborted = false;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;
};

BundleReport solve_bundle(const IdealCamera& camera, BundleProblem& problem, const BundleSettings& settings,
                          const std::atomic<bool>* abort);

}  // namespace labo::slam
