#include "localization/estimation/reacquisition_gate.hpp"

namespace labo::estimation {

void ReacquisitionGate::reset() {
  has_previous_ = false;
  open_ = false;
  refused_in_row_ = 0;
}

ReacquisitionGate::Verdict ReacquisitionGate::check(const Eigen::Vector4d& innovation, double mahalanobis2, Seconds t,
                                                    Seconds gap_s) {
  if (has_previous_ && t - previous_t_ > gap_s) reset();  // lost in between: a new re-acquisition
  const bool agrees_with_previous =
      has_previous_ && (innovation.head<3>() - previous_innovation_.head<3>()).norm() <= settings_.confirm_spread_m;
  has_previous_ = true;
  previous_t_ = t;
  previous_innovation_ = innovation;
  if (open_) return Verdict::Accepted;
  if (mahalanobis2 <= settings_.chi2 && innovation.head<3>().norm() <= settings_.max_jump_m) {
    open_ = true;
    refused_in_row_ = 0;
    return Verdict::Accepted;
  }
  // A refused pose: it outvotes the estimate only by persisting with the same offset.
  refused_in_row_ = agrees_with_previous ? refused_in_row_ + 1 : 1;
  if (refused_in_row_ >= settings_.confirm_frames) {
    open_ = true;
    refused_in_row_ = 0;
    return Verdict::Confirmed;
  }
  return Verdict::Refused;
}

}  // namespace labo::estimation
