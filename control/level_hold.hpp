#pragma once
// Commands the safety monitor flies when the mission is paused, instead of the firmware's hover.
// The AR.Drone's own hover holds whatever altitude it starts at and does not turn: after a vertical
// push it keeps the drone above the set point, with the panel out of view, for as long as the hover
// lasts. These keep altitude and yaw under control while braking the horizontal motion on the
// measured velocity only (bottom-camera velocities stay good when the position estimate does not),
// so they are safe with a position estimate in doubt. Test
// "control: a level hold keeps the altitude and yaw of the set point, braking on the velocity".
//  - level_hold_command: brake horizontally, hold the altitude and yaw given;
//  - climb_command: brake horizontally, climb (too close to the surface below), yaw held still.
#include "control/control_config.hpp"
#include "localization/fusion/localization_pipelines.hpp"
#include "drone/drone_link.hpp"

namespace labo::control {

MoveCommand level_hold_command(const fusion::PoseEstimate& pose, double target_z_m, double target_yaw_rad,
                               const PoseControlGains& gains);
MoveCommand climb_command(const fusion::PoseEstimate& pose, const PoseControlGains& gains);

}  // namespace labo::control
