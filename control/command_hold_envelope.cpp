#include "control/command_hold_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace labo::control {

namespace {
constexpr double kG = 9.81;
// The firmware's hover brakes at about half its full tilt: a cautious figure, since its velocity
// gain is the firmware's and not in our model.
constexpr double kHoverBrakeShare = 0.5;
constexpr int kBisections = 8;
}  // namespace

CommandHoldEnvelope::CommandHoldEnvelope(const Eigen::Vector3d& room_min, const Eigen::Vector3d& room_max,
                                         double clearance_m, double hold_s, const estimation::MotionModelConstants& model)
    : min_(room_min.array() + clearance_m), max_(room_max.array() - clearance_m), hold_s_(hold_s), model_(model) {
  // Below, the firmware and the ultrasound clearance keep the drone off the floor (and landing is
  // meant to reach it): only the walls and the ceiling bound the rest point.
  min_.z() = -std::numeric_limits<double>::infinity();
}

double CommandHoldEnvelope::outside_by(const Eigen::Vector3d& p) const {
  return (min_ - p).cwiseMax(0.0).sum() + (p - max_).cwiseMax(0.0).sum();
}

Eigen::Vector3d CommandHoldEnvelope::rest_point(const MoveCommand& c, const HoldEnvelopeInputs& s) const {
  // Horizontal: the commanded tilt's acceleration over the hold without drag (drag only slows the
  // drone, and the model's drag is its least certain constant: in a lockstep cut the drone kept
  // 1.1 m/s for a second where the model's drag would have taken 40 % of it), then the hover's braking
  // distance v^2 / (2 a_brake). An upper bound on the travel, not an estimate.
  const double forward = std::tan(model_.tilt_max_rad * std::clamp(c.pitch, -1.0, 1.0)) * kG;
  const double right = std::tan(model_.tilt_max_rad * std::clamp(c.roll, -1.0, 1.0)) * kG;
  const double cy = std::cos(s.yaw_rad), sy = std::sin(s.yaw_rad);
  const Eigen::Vector2d a_cmd(cy * forward + sy * right, sy * forward - cy * right);  // right = -y in the body
  const Eigen::Vector2d v0 = s.velocity_mps.head<2>();
  const Eigen::Vector2d travel = v0 * hold_s_ + 0.5 * a_cmd * hold_s_ * hold_s_;
  const Eigen::Vector2d v_end = v0 + a_cmd * hold_s_;
  const double a_brake = kHoverBrakeShare * kG * std::tan(model_.tilt_max_rad);
  const Eigen::Vector2d braking = v_end.norm() > 1e-9 ? Eigen::Vector2d(v_end * (v_end.norm() / (2.0 * a_brake))) : Eigen::Vector2d::Zero();
  // Vertical: the firmware's vertical-speed loop reaches vz_max * gaz within a fraction of a second.
  const double vz = model_.vz_max_mps * std::clamp(c.gaz, -1.0, 1.0);
  Eigen::Vector3d rest = s.position_m;
  rest.head<2>() += travel + braking;
  rest.z() += vz * hold_s_;
  return rest;
}

HoldEnvelopeResult CommandHoldEnvelope::limit(const MoveCommand& command, const HoldEnvelopeInputs& s) const {
  HoldEnvelopeResult r;
  r.move = command;
  auto scaled = [&](double f) {
    MoveCommand m = command;
    m.roll *= f;
    m.pitch *= f;
    if (m.gaz > 0) m.gaz *= f;  // a climb held into the ceiling; a descent is the firmware's to stop
    return m;
  };
  const double as_sent = outside_by(rest_point(command, s));
  if (as_sent == 0.0) return r;
  const double untilted = outside_by(rest_point(scaled(0.0), s));
  if (untilted > 0.0) {
    // Too fast (or too near a wall) for any scaled command: one that already brakes or leads away
    // stays; one that makes it worse becomes a hover.
    if (as_sent <= untilted) return r;
    r.hover = true;
    r.scale = 0.0;
    r.move = MoveCommand{};
    return r;
  }
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < kBisections; ++i) {
    const double mid = 0.5 * (lo + hi);
    (outside_by(rest_point(scaled(mid), s)) == 0.0 ? lo : hi) = mid;
  }
  r.scale = lo;
  r.move = scaled(lo);
  return r;
}

}  // namespace labo::control
