#pragma once
// The SLAM map's metric scale and its placement in the world.
//
// ScaleEstimator: maximum-likelihood scale lambda from pairs (q_i map displacement, m_i metric
// displacement) with m_i ~ lambda * q_i, isotropic noise on both sides (closed form,
// notes/tum_ardrone.md §3). Beyond tum_ardrone:
//  - both noises are given in metres (the map side is converted with the current scale), so the
//    estimator weighs the two sides the same whatever the map's unit is (a monocular map's unit is its
//    initial median depth: 6-10 m in the simulated lab);
//  - a monocular map's scale drifts (in the simulated lab from 10 to 6 m/unit within 20 s of the
//    map's start, docs/state-estimation.md): older pairs are forgotten with a weight
//    (1 - 1/memory_pairs)^age, so the estimate follows the map of now;
//  - outliers: each pair's residual |m_i - lambda_ref q_i| against the weighted median of the
//    single-pair scales is tested with a chi2 gate (3 dof) under the same noise model, instead of
//    tum_ardrone's 0.2x-5x band around the median;
//  - a map whose scale jumps (its adjustment after the first motion along the optical axis: 10 -> 6
//    m/unit in the lab): when the newest 2-6 pairs agree with each other on a scale more than 3 sigma
//    away from the estimate, the estimate restarts from them (scale_changes()).
//
// MapToWorld: the similarity T_world_map (rotation R, translation t, scale lambda):
// p_world = R * lambda * p_map + t. When the scale changes, the translation is updated so the
// fixpoint (a map point chosen at initialisation) keeps its world position.
#include <Eigen/Geometry>
#include <utility>
#include <vector>

namespace labo::estimation {

struct ScaleStatus {
  double scale = 1.0;
  double accuracy = 0.0;     // 0.5 + 0.5*clip(S_PI*lambda/4, 0, 1) as tum_ardrone publishes; 0 before any pair
  int pairs = 0;             // pairs kept (the most recent ones; older ones weigh almost nothing)
  int inliers = 0;
  bool estimated = false;    // at least kMinInliers inlier pairs: SLAM poses are fused from then on
  double relative_std = 1.0; // spread of the inlier single-pair scales / sqrt(n), relative
};

struct ScaleSettings {
  double sigma_map_m = 0.02;           // noise of one (weighted) map displacement, metres at the current scale
  double sigma_metric_m = 0.02;        // noise of one (weighted) metric displacement
  double min_displacement_m = 0.2;     // (weighted) metric displacement a pair must reach to carry information:
                                       // with the default axis weights, 7 cm of climb or 20 cm sideways
  double memory_pairs = 10.0;          // forgetting: a pair's weight is (1 - 1/memory_pairs)^age (the map's scale drifts)
  double outlier_chi2 = 11.34;         // residual gate (3 dof, 99 %)
  double initial_scale = 1.0;
};

class ScaleEstimator {
 public:
  static constexpr int kMinInliers = 3;
  static constexpr int kChangeMinPairs = 2;
  static constexpr int kChangeMaxPairs = 6;

  explicit ScaleEstimator(const ScaleSettings& settings);

  // One pair of displacements (already weighted per axis by the caller, the same weights on both).
  // Pairs whose metric displacement is below min_displacement_m, whose map displacement is zero or
  // which point the other way are ignored; returns whether the pair was kept.
  bool add_pair(const Eigen::Vector3d& map_displacement, const Eigen::Vector3d& metric_displacement);
  void reset(double initial_scale);

  double scale() const { return status_.scale; }
  const ScaleStatus& status() const { return status_; }
  // Pairs the chi2 gate refused when they arrived (counted once each).
  int outliers_at_arrival() const { return outliers_at_arrival_; }
  // Times the map's scale was found to have changed (the estimate restarted from the newest pairs).
  int scale_changes() const { return scale_changes_; }

  // The ML estimate for sums S_PP, S_II, S_PI (exposed for tests).
  static double ml_scale(double s_pp, double s_ii, double s_pi, double sigma_map, double sigma_metric);

 private:
  struct Pair {
    Eigen::Vector3d map;
    Eigen::Vector3d metric;
    double alpha;  // the pair's own scale |m| / |q|
  };
  double weighted_median_scale();  // of the single-pair scales, with the forgetting weights
  bool inlier(const Pair& p, double reference) const;
  int changed_pairs() const;  // how many newest pairs show a changed scale (0: none)
  void recompute();

  ScaleSettings settings_;
  std::vector<Pair> pairs_;
  std::vector<double> weights_;                   // forgetting weight of each pair
  std::vector<std::pair<double, double>> sorted_; // (alpha, weight), scratch for the median
  int outliers_at_arrival_ = 0;
  int scale_changes_ = 0;
  bool was_estimated_ = false;  // a restart after a scale change keeps the map's scale known
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

}  // namespace labo::estimation
