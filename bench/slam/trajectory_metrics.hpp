#pragma once
// Trajectory error metrics, as evo computes them for monocular SLAM: the estimated camera centres are
// aligned to ground truth with a similarity transform (Umeyama, 7 DoF), then the absolute
// trajectory error is the RMSE of the aligned positions; the relative pose error compares motions
// over a fixed interval (translation scaled by the alignment's scale); scale drift compares the
// scales fitted on the first and the last third of the trajectory.
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace labo::bench {

struct PosePair {
  Seconds t;
  Eigen::Isometry3d estimate_T_map_cam;
  Eigen::Isometry3d truth_T_world_cam;
};

struct Sim3 {
  double scale = 1;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * R * p + t; }
};

std::optional<Sim3> align_sim3(const std::vector<PosePair>& pairs);

struct TrajectoryErrors {
  int poses = 0;
  double ate_rmse_m = 0;
  double ate_max_m = 0;
  double rpe_translation_rmse_m = 0;  // over `rpe_interval_s`
  double rpe_rotation_rmse_deg = 0;
  double scale_drift_percent = 0;
  double alignment_scale = 1;
  // Angle the estimate turned, as a fraction of the angle the truth turned, minus 1 (percent): each
  // motion between consecutive poses (camera frame) projected on the true motion's axis, summed, over
  // the true angles summed. A systematic error (focal length, lens model, pixel convention) shows up
  // here as a constant ratio; random errors cancel. 0 when the truth turned less than 90 deg.
  double rotation_scale_error_percent = 0;
  double truth_turned_deg = 0;
};

std::optional<TrajectoryErrors> trajectory_errors(const std::vector<PosePair>& pairs, Seconds rpe_interval_s = 1.0);

// Where along the flight the error is: the RMSE of the positions aligned by the whole trajectory's
// Sim(3), over consecutive windows of `window_s` (empty windows give 0).
std::vector<double> windowed_ate_m(const std::vector<PosePair>& pairs, Seconds window_s);

// Writes a trajectory in the TUM format ("t tx ty tz qx qy qz qw" per line), the estimate or the
// ground truth, so that evo and other tools can evaluate it. Throws std::runtime_error on I/O errors.
void write_tum_trajectory(const std::string& file, const std::vector<PosePair>& pairs, bool ground_truth);

}  // namespace labo::bench
