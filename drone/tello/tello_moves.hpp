#pragma once
// The SDK's distance moves as TelloFirmware flies them (docs/tello.md "TelloEmulator"): "up/down/
// left/right/forward/back x" (20-500 cm), "cw/ccw x" (1-360 deg), "go x y z speed" (-500-500 cm,
// 10-100 cm/s; x, y and z not all within +-20), "curve x1 y1 z1 x2 y2 z2 speed" (the same, 10-60
// cm/s, an arc of radius 0.5-10 m), "flip l|r|f|b". Out-of-range arguments give the reason the
// reply carries after "error". The frame of a move is the drone's at its start: x forward, y left,
// z up (LaboDrone's body frame; the SDK document does not say which way its y points).
//
// MoveFlight flies one over its vehicle's own odometry (the telemetry's velocities integrated, the
// altitude and heading as measured), as a Tello flies them over its downward vision: a velocity loop
// toward the next waypoint, at the move's speed, done when settled there. No I/O, no allocation per
// step.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "drone/drone_link.hpp"

namespace labo::tello {

struct MovePlan {
  std::vector<Eigen::Vector3d> waypoints;  // in the start's frame (m); the last is the goal
  double turn_rad = 0;                     // counter-clockwise (cw x: negative)
  double speed_mps = 0.1;
  bool flip = false;                       // flown as a hover of kFlipS: the simulated vehicle cannot flip
};

inline constexpr double kFlipS = 1.0;
inline constexpr double kMinFlipBatteryPercent = 50.0;  // a Tello refuses a flip below this

struct MoveParse {
  bool is_move = false;        // the word is one of the distance moves
  std::optional<MovePlan> plan;
  std::string error;           // why the arguments are refused ("" when planned)
};
// `speed_cmps`: the "speed" setting, for the moves that take none.
MoveParse parse_distance_move(std::string_view word, std::string_view args, int speed_cmps);

// Where the vehicle is by its own account: odometry in a frame fixed at the first update.
struct MoveOdometry {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  Eigen::Vector3d velocity_body_mps = Eigen::Vector3d::Zero();
};

class MoveFlight {
 public:
  MoveFlight(MovePlan plan, const MoveOdometry& start, Seconds t);
  enum class Status { Flying, Done, TimedOut };
  // One control step at t: the sticks (MoveCommand fractions) to fly now.
  Status step(const MoveOdometry& now, Seconds t, MoveCommand& command);

 private:
  Eigen::Vector3d world_of(const Eigen::Vector3d& in_start_frame) const;

  MovePlan plan_;
  MoveOdometry start_;
  Seconds start_t_ = 0, deadline_t_ = 0;
  std::size_t next_ = 0;  // the waypoint flown to
  double last_yaw_rad_ = 0, turned_rad_ = 0;
};

}  // namespace labo::tello
