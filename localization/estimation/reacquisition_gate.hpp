#pragma once
// ReacquisitionGate: a vision source's first poses after it was lost (a panel re-detected, SLAM
// relocalized, a face found again) are compared with the dead-reckoned estimate before they may
// correct it. While a source is established the estimator's innovation gate watches it; without this
// gate nothing would watch its re-acquisition, and a wrong re-detection (after a vertical push took
// the panel out of view, a false homography 0.5-1.5 m off) would drag the estimate at once and fly
// the drone into the bench. Test "estimation: a wrong re-detection 1 m off after a loss does not
// drive the estimate".
//
// A pose is accepted at once when its innovation (observed - estimated x, y, z, yaw) is within both
// bounds: the squared Mahalanobis distance under the estimate's and the observation's covariance
// (chi2), and a metric bound on the position innovation (max_jump_m), which holds even when a long
// dead reckoning has grown the covariance so much that any jump looks plausible. Otherwise it is
// refused, unless it persists: confirm_frames frames in a row whose innovations agree from frame to
// frame within confirm_spread_m say the estimate, not the vision, is wrong; the source is then
// accepted (a re-sync) until it is lost again. A gap longer than gap_s between checks starts over.
// One gate per source; deterministic, no allocation.
#include <Eigen/Core>

#include "core/time.hpp"

namespace labo::estimation {

struct ReacquisitionSettings {
  double chi2 = 16.0;              // 4 dof: about the 99.7 % quantile
  double max_jump_m = 0.5;         // position innovation accepted at once, whatever the covariance
  int confirm_frames = 15;         // a refused pose persisting this many frames is accepted (0.5 s at 30 fps)
  double confirm_spread_m = 0.10;  // ... when consecutive innovations agree within this
};

class ReacquisitionGate {
 public:
  enum class Verdict {
    Accepted,   // within the bounds (or the source was confirmed): fuse
    Confirmed,  // refused poses persisted and agreed: fuse from now on (a re-sync)
    Refused,    // a jump the estimate's uncertainty does not allow: not fused
  };

  explicit ReacquisitionGate(const ReacquisitionSettings& settings = {}) : settings_(settings) {}

  // innovation: observed - estimated (x, y, z in m, yaw in rad); mahalanobis2 its squared distance;
  // gap_s: a longer pause since the previous check means the source was lost in between.
  Verdict check(const Eigen::Vector4d& innovation, double mahalanobis2, Seconds t, Seconds gap_s);
  // The source is established again (its innovation gate takes over) or was reset.
  void reset();

  int refused_in_row() const { return refused_in_row_; }
  bool open() const { return open_; }

 private:
  ReacquisitionSettings settings_;
  bool has_previous_ = false;
  Seconds previous_t_ = 0;
  bool open_ = false;  // accepted or confirmed since the last gap
  int refused_in_row_ = 0;
  Eigen::Vector4d previous_innovation_ = Eigen::Vector4d::Zero();
};

}  // namespace labo::estimation
