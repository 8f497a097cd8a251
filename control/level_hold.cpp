#include "control/level_hold.hpp"

#include <algorithm>

#include "control/pid_controller.hpp"
#include "core/frames.hpp"

namespace labo::control {

namespace {
constexpr double kClimbGaz = 0.5;  // about 0.35 m/s on the AR.Drone

// Horizontal braking on the velocity: the position terms of the xy PID are left out on purpose.
void brake(const fusion::PoseEstimate& pose, const PoseControlGains& gains, MoveCommand& cmd) {
  Eigen::Vector2d u = -gains.xy.kd * pose.velocity_world.head<2>();
  if (u.norm() > gains.max_tilt_command) u *= gains.max_tilt_command / u.norm();
  const Eigen::Vector2d u_body = world_to_body_xy(u, ypr_from_rotation(pose.T_world_body.linear())[0]);
  cmd.pitch = u_body.x();
  cmd.roll = -u_body.y();
}
}  // namespace

MoveCommand level_hold_command(const fusion::PoseEstimate& pose, double target_z_m, double target_yaw_rad,
                               const PoseControlGains& gains) {
  MoveCommand cmd;
  brake(pose, gains, cmd);
  const double ez = target_z_m - pose.T_world_body.translation().z();
  cmd.gaz = std::clamp(gains.z.kp * ez - gains.z.kd * pose.velocity_world.z(), gains.z.out_min, gains.z.out_max);
  const double eyaw = wrap_angle(target_yaw_rad - ypr_from_rotation(pose.T_world_body.linear())[0]);
  cmd.yaw_rate = std::clamp(gains.yaw.kp * eyaw - gains.yaw.kd * pose.yaw_rate, gains.yaw.out_min, gains.yaw.out_max);
  return cmd;
}

MoveCommand climb_command(const fusion::PoseEstimate& pose, const PoseControlGains& gains) {
  MoveCommand cmd;
  brake(pose, gains, cmd);
  cmd.gaz = std::min(kClimbGaz, gains.z.out_max);
  cmd.yaw_rate = 0;
  return cmd;
}

}  // namespace labo::control
