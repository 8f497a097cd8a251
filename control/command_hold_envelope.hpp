#pragma once
// Keeps every move command one the drone survives a link cut with. A cut AR.Drone 2.0 goes on with
// the last command it received until its com watchdog fires (estimation.firmware_command_hold_s,
// 2 s) and only then hovers: a drone sent fast at a wall just before a cut keeps its tilt for those
// seconds and flies into it. The envelope bounds, with the estimator's own motion model (its tilt,
// without drag), where the drone would come to rest if the command were held that long and the
// firmware's hover then braked it; when that point lies beyond the walls or the ceiling shrunk by `clearance_m`, the
// command's horizontal (and upward) parts are scaled down until it does not. A drone already too fast
// (or too near a wall) for any scaled command keeps a command that brakes or leads away and is told
// to hover otherwise (the firmware's hover brakes actively, and is also what a cut keeps). Pure
// function of its inputs: no clock, no state.
#include <Eigen/Core>

#include "drone/drone_link.hpp"
#include "localization/estimation/estimation_config.hpp"

namespace labo::control {

struct HoldEnvelopeInputs {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  // world
  double yaw_rad = 0;
};

struct HoldEnvelopeResult {
  MoveCommand move;
  bool hover = false;    // no scaled command keeps it inside: hover instead
  double scale = 1.0;    // the factor applied to roll and pitch (1: untouched)
  bool limited() const { return hover || scale < 1.0; }
};

class CommandHoldEnvelope {
 public:
  CommandHoldEnvelope(const Eigen::Vector3d& room_min, const Eigen::Vector3d& room_max, double clearance_m,
                      double hold_s, const estimation::MotionModelConstants& model);

  HoldEnvelopeResult limit(const MoveCommand& command, const HoldEnvelopeInputs& state) const;
  // Where the drone would stop (x, y, z) if `command` were held for the hold time and then the
  // firmware hovered.
  Eigen::Vector3d rest_point(const MoveCommand& command, const HoldEnvelopeInputs& state) const;

 private:
  // How far (m, summed over the axes) `p` lies outside the walls and below the ceiling; 0 inside.
  double outside_by(const Eigen::Vector3d& p) const;

  Eigen::Vector3d min_, max_;
  double hold_s_;
  estimation::MotionModelConstants model_;
};

}  // namespace labo::control
