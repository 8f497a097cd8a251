#pragma once
// The SLAM map's metric scale and its placement in the world.
//
// ScaleEstimator: maximum-likelihood scale lambda from pairs (p_i map displacement, m_i metric
// displacement) with m_i ~ lambda * p_i, isotropic noise sigma_map on p and sigma_metric on m
// (closed form, notes/tum_ardrone.md §3). Single-pair estimates reject outliers around their median.
//
// MapToWorld: the similarity T_world_map (rotation R, translation t, scale lambda):
// p_world = R * lambda * p_map + t. When the scale changes, the translation is updated so the
// fixpoint (a map point chosen at initialisation) keeps its world position.
#include <Eigen/Geometry>
#include <vector>

namespace labo {

struct ScaleStatus {
  double scale = 1.0;
  double accuracy = 0.0;     // 0.5 + 0.5*clip(S_PI*lambda/4, 0, 1) as tum_ardrone publishes; 0 before any pair
  int pairs = 0;
  int inliers = 0;
  bool estimated = false;    // at least one accepted pair
  double relative_std = 1.0; // spread of the inlier single-pair scales / sqrt(n), relative
};

class ScaleEstimator {
 public:
  ScaleEstimator(double sigma_map, double sigma_metric, double pair_sigma_metric, double initial_scale);

  // One pair of displacements (already weighted per axis by the caller). Pairs where either vector is
  // shorter than 5 cm are ignored; returns whether the pair was kept.
  bool add_pair(const Eigen::Vector3d& map_displacement, const Eigen::Vector3d& metric_displacement);
  void reset(double initial_scale);

  double scale() const { return status_.scale; }
  const ScaleStatus& status() const { return status_; }

  // The ML estimate for sums S_PP, S_II, S_PI (exposed for tests).
  static double ml_scale(double s_pp, double s_ii, double s_pi, double sigma_map, double sigma_metric);

 private:
  void recompute();

  double sigma_map_;
  double sigma_metric_;
  double pair_sigma_metric_;
  double initial_scale_;
  std::vector<Eigen::Vector3d> map_;
  std::vector<Eigen::Vector3d> metric_;
  std::vector<double> pair_scales_;
  ScaleStatus status_;
};

class MapToWorld {
 public:
  bool initialized() const { return initialized_; }
  // Places the map so that T_world_cam_map (a camera pose in the map) lands on T_world_cam.
  void initialize(const Eigen::Isometry3d& T_map_cam, const Eigen::Isometry3d& T_world_cam, double scale);
  // Averages the rotation with a new alignment (first frames only, rotations near each other).
  void refine_rotation(const Eigen::Isometry3d& T_map_cam, const Eigen::Isometry3d& T_world_cam, double weight);
  void set_scale(double new_scale);  // keeps the fixpoint's world position
  void reset() { initialized_ = false; }

  double scale() const { return scale_; }
  const Eigen::Matrix3d& R_world_map() const { return R_; }
  const Eigen::Vector3d& t_world_map() const { return t_; }
  // A camera pose in the map (map units) to metric world coordinates.
  Eigen::Isometry3d T_world_cam(const Eigen::Isometry3d& T_map_cam) const;
  // A map displacement expressed in world axes, still in map units (for the scale pairs).
  Eigen::Vector3d rotate_to_world(const Eigen::Vector3d& d_map) const { return R_ * d_map; }

 private:
  bool initialized_ = false;
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
  double scale_ = 1.0;
  Eigen::Vector3d fixpoint_map_ = Eigen::Vector3d::Zero();
};

}  // namespace labo
