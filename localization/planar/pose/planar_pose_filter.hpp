#pragma once
// PlanarPoseFilter: fuses a planar object's orientation over frames, weighted by each frame's
// rotation_sigma_rad (PlanarResult). At 2-3 m one frame of a 0.40 x 0.20 m panel (~90 x 45 px)
// determines its tilt to ~2 deg (docs/planar.md); frames are nearly independent there, so averaging a
// few of them is the way below 1 deg. Motion model: constant angular velocity of the object in the
// camera frame (the drone turns smoothly), white angular acceleration of `angular_accel_radps2` (per
// sqrt(s)); a Kalman filter on the rotation's tangent space, one (angle, rate) pair per axis sharing
// one 2x2 covariance (the sigma is isotropic). The position is left per frame (already ~0.1 % of range).
//
// Honest by construction: causal (past frames only), no truth; it lags when the object turns faster
// than the model expects, and `bench planar` reports its error next to the per-frame one.
// An innovation beyond `gate_chi2` (3 dof) is skipped; `max_skipped` in a row, or a gap longer than
// `max_gap_s`, restart the filter from the measurement.
#include <Eigen/Geometry>
#include <optional>

#include "core/time.hpp"

namespace labo::planar {

struct PlanarPoseFilterSettings {
  double angular_accel_radps2 = 0.3;  // rad/s^2 per sqrt(s): a hovering drone's slow sway, not its kicks
  double initial_rate_sigma_radps = 0.5;
  double gate_chi2 = 16.0;
  int max_skipped = 3;
  Seconds max_gap_s = 0.25;
};

struct FilteredOrientation {
  Eigen::Matrix3d R_cam_object = Eigen::Matrix3d::Identity();
  double rotation_sigma_rad = 0;  // 1-sigma per axis after the update
  bool restarted = false;         // this measurement (re)started the filter
  bool skipped = false;           // this measurement failed the gate (the prediction is returned)
};

class PlanarPoseFilter {
 public:
  explicit PlanarPoseFilter(PlanarPoseFilterSettings settings = {});

  // One measured orientation at time t with its 1-sigma (> 0 and finite; otherwise the filter restarts
  // from this measurement with 0.1 rad).
  FilteredOrientation update(const Eigen::Matrix3d& R_cam_object, double rotation_sigma_rad, Seconds t);
  void reset() { state_.reset(); }

 private:
  struct State {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d rate = Eigen::Vector3d::Zero();  // rad/s, camera frame
    Eigen::Matrix2d P = Eigen::Matrix2d::Identity();  // (angle, rate) per axis
    Seconds t = 0;
    int skipped = 0;
  };
  FilteredOrientation restart(const Eigen::Matrix3d& R, double variance, Seconds t);

  PlanarPoseFilterSettings settings_;
  std::optional<State> state_;
};

}  // namespace labo::planar
