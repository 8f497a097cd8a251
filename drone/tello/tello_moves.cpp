#include "drone/tello/tello_moves.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace labo::tello {

namespace {

constexpr int kMinDistanceCm = 20, kMaxDistanceCm = 500;
constexpr int kMinTurnDeg = 1, kMaxTurnDeg = 360;
constexpr int kMaxCoordinateCm = 500, kDeadZoneCm = 20;
constexpr int kMinGoSpeed = 10, kMaxGoSpeed = 100, kMaxCurveSpeed = 60;
constexpr double kMinArcRadiusM = 0.5, kMaxArcRadiusM = 10.0;
constexpr double kArcStepM = 0.1;  // the arc flown as waypoints this far apart

// The loops: a velocity toward the waypoint (gain per second, capped at the move's speed), a stick
// fraction per m/s of velocity error; the vertical stick is a fraction of the vehicle's climb rate,
// the yaw stick of its turn rate (the simulated lab's AR.Drone limits, docs/sim.md).
constexpr double kPositionGainPerS = 1.0;
constexpr double kVelocityToStick = 0.8;
constexpr double kMaxClimbMps = 0.7;
constexpr double kMaxTurnRadps = 100.0 * std::numbers::pi / 180.0;
constexpr double kTurnRateRadps = 60.0 * std::numbers::pi / 180.0;
constexpr double kTurnGainPerS = 2.0;
// Settled: within these of the goal.
constexpr double kReachedM = 0.05, kSettledMps = 0.08, kTurnedRad = 2.0 * std::numbers::pi / 180.0;
constexpr double kPassWaypointM = 0.15;  // an arc's intermediate waypoint is passed this close
constexpr double kTimeoutMarginS = 8.0;

bool read_int(std::string_view& args, int& value) {
  while (!args.empty() && args.front() == ' ') args.remove_prefix(1);
  const auto [end, ec] = std::from_chars(args.data(), args.data() + args.size(), value);
  if (ec != std::errc() || end == args.data()) return false;
  args.remove_prefix(static_cast<std::size_t>(end - args.data()));
  return args.empty() || args.front() == ' ';
}

// Reads exactly N integers.
template <std::size_t N>
bool read_ints(std::string_view args, std::array<int, N>& values) {
  for (int& v : values)
    if (!read_int(args, v)) return false;
  while (!args.empty() && args.front() == ' ') args.remove_prefix(1);
  return args.empty();
}

std::string range_text(const char* what, int lo, int hi) {
  return std::string(what) + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
}

bool in_range(int v, int lo, int hi) { return v >= lo && v <= hi; }

bool all_in_dead_zone(int x, int y, int z) {
  return std::abs(x) <= kDeadZoneCm && std::abs(y) <= kDeadZoneCm && std::abs(z) <= kDeadZoneCm;
}

Eigen::Vector3d metres(int x, int y, int z) { return Eigen::Vector3d(x, y, z) / 100.0; }

MoveParse refused(std::string why) { return MoveParse{true, std::nullopt, std::move(why)}; }

MoveParse planned(MovePlan plan) { return MoveParse{true, std::move(plan), ""}; }

MoveParse straight(std::string_view word, std::string_view args, double speed_mps) {
  std::array<int, 1> d{};
  if (!read_ints(args, d)) return refused("expected one integer distance in cm");
  if (!in_range(d[0], kMinDistanceCm, kMaxDistanceCm)) return refused(range_text("distance", kMinDistanceCm, kMaxDistanceCm));
  const double m = d[0] / 100.0;
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();
  if (word == "up") goal.z() = m;
  if (word == "down") goal.z() = -m;
  if (word == "forward") goal.x() = m;
  if (word == "back") goal.x() = -m;
  if (word == "left") goal.y() = m;
  if (word == "right") goal.y() = -m;
  return planned(MovePlan{{goal}, 0.0, speed_mps, false});
}

MoveParse turn(std::string_view word, std::string_view args, double speed_mps) {
  std::array<int, 1> d{};
  if (!read_ints(args, d)) return refused("expected one integer angle in degrees");
  if (!in_range(d[0], kMinTurnDeg, kMaxTurnDeg)) return refused(range_text("angle", kMinTurnDeg, kMaxTurnDeg));
  const double rad = d[0] * std::numbers::pi / 180.0;
  return planned(MovePlan{{Eigen::Vector3d::Zero()}, word == "ccw" ? rad : -rad, speed_mps, false});
}

MoveParse go(std::string_view args) {
  std::array<int, 4> v{};
  if (!read_ints(args, v)) return refused("expected x y z speed, integers");
  for (int i = 0; i < 3; ++i)
    if (!in_range(v[i], -kMaxCoordinateCm, kMaxCoordinateCm)) return refused(range_text("x, y, z", -kMaxCoordinateCm, kMaxCoordinateCm));
  if (!in_range(v[3], kMinGoSpeed, kMaxGoSpeed)) return refused(range_text("speed", kMinGoSpeed, kMaxGoSpeed));
  if (all_in_dead_zone(v[0], v[1], v[2])) return refused("x, y and z all within [-20, 20]");
  return planned(MovePlan{{metres(v[0], v[1], v[2])}, 0.0, v[3] / 100.0, false});
}

// The arc from the start (the origin) through p1 to p2, as waypoints kArcStepM apart.
MoveParse curve(std::string_view args) {
  std::array<int, 7> v{};
  if (!read_ints(args, v)) return refused("expected x1 y1 z1 x2 y2 z2 speed, integers");
  for (int i = 0; i < 6; ++i)
    if (!in_range(v[i], -kMaxCoordinateCm, kMaxCoordinateCm)) return refused(range_text("coordinates", -kMaxCoordinateCm, kMaxCoordinateCm));
  if (!in_range(v[6], kMinGoSpeed, kMaxCurveSpeed)) return refused(range_text("speed", kMinGoSpeed, kMaxCurveSpeed));
  if (all_in_dead_zone(v[0], v[1], v[2]) || all_in_dead_zone(v[3], v[4], v[5]))
    return refused("x, y and z of a point all within [-20, 20]");
  const Eigen::Vector3d a = metres(v[0], v[1], v[2]), b = metres(v[3], v[4], v[5]);
  // The circle through 0, a, b: its centre c = alpha a + beta b with |c - a| = |c| = |c - b|.
  const Eigen::Vector3d n = a.cross(b);
  if (n.squaredNorm() < 1e-12) return refused("the start and the two points lie on a line: no arc");
  const Eigen::Vector3d c = (a.squaredNorm() * b - b.squaredNorm() * a).cross(n) / (2.0 * n.squaredNorm());
  const double radius = c.norm();
  if (radius < kMinArcRadiusM || radius > kMaxArcRadiusM) return refused("arc radius out of range [0.5, 10] m");
  // Angles about the normal from the start's direction to a and to b: the arc goes the way that passes a.
  const Eigen::Vector3d u = (-c).normalized(), w = n.normalized().cross(u);
  auto angle_of = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d r = p - c;
    double ang = std::atan2(r.dot(w), r.dot(u));
    return ang < 0 ? ang + 2.0 * std::numbers::pi : ang;
  };
  const double to_b = angle_of(b);
  MovePlan plan{{}, 0.0, v[6] / 100.0, false};
  const int steps = std::max(1, static_cast<int>(std::ceil(radius * to_b / kArcStepM)));
  for (int i = 1; i <= steps; ++i) {
    const double ang = to_b * i / steps;
    plan.waypoints.push_back(c + radius * (std::cos(ang) * u + std::sin(ang) * w));
  }
  return planned(std::move(plan));
}

}  // namespace

MoveParse parse_distance_move(std::string_view word, std::string_view args, int speed_cmps) {
  const double speed_mps = speed_cmps / 100.0;
  if (word == "up" || word == "down" || word == "left" || word == "right" || word == "forward" || word == "back")
    return straight(word, args, speed_mps);
  if (word == "cw" || word == "ccw") return turn(word, args, speed_mps);
  if (word == "go") return go(args);
  if (word == "curve") return curve(args);
  if (word == "flip") {
    if (args != "l" && args != "r" && args != "f" && args != "b") return refused("expected l, r, f or b");
    return planned(MovePlan{{Eigen::Vector3d::Zero()}, 0.0, speed_mps, true});
  }
  return MoveParse{};
}

MoveFlight::MoveFlight(MovePlan plan, const MoveOdometry& start, Seconds t)
    : plan_(std::move(plan)), start_(start), start_t_(t), last_yaw_rad_(start.yaw_rad) {
  double length = 0;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  for (const auto& p : plan_.waypoints) {
    length += (p - from).norm();
    from = p;
  }
  deadline_t_ = t + length / std::max(0.01, plan_.speed_mps) + std::abs(plan_.turn_rad) / kTurnRateRadps + kTimeoutMarginS;
}

Eigen::Vector3d MoveFlight::world_of(const Eigen::Vector3d& p) const {
  return start_.position_m + Eigen::AngleAxisd(start_.yaw_rad, Eigen::Vector3d::UnitZ()) * p;
}

MoveFlight::Status MoveFlight::step(const MoveOdometry& now, Seconds t, MoveCommand& command) {
  command = MoveCommand{};
  if (plan_.flip) return t - start_t_ >= kFlipS ? Status::Done : Status::Flying;
  if (t > deadline_t_) return Status::TimedOut;
  const bool last = next_ + 1 >= plan_.waypoints.size();
  const Eigen::Vector3d error_world = world_of(plan_.waypoints[next_]) - now.position_m;
  if (!last && error_world.norm() < kPassWaypointM) ++next_;
  // The velocity wanted, capped at the move's speed, in the body frame (x forward, y left, z up).
  Eigen::Vector3d v_wanted = kPositionGainPerS * error_world;
  if (v_wanted.norm() > plan_.speed_mps) v_wanted *= plan_.speed_mps / v_wanted.norm();
  const Eigen::Vector3d v_body = Eigen::AngleAxisd(-now.yaw_rad, Eigen::Vector3d::UnitZ()) * v_wanted;
  const Eigen::Vector3d dv = v_body - now.velocity_body_mps;
  command.pitch = std::clamp(kVelocityToStick * dv.x(), -1.0, 1.0);   // pitch > 0: forward
  command.roll = std::clamp(-kVelocityToStick * dv.y(), -1.0, 1.0);   // roll > 0: right, -y
  command.gaz = std::clamp(v_body.z() / kMaxClimbMps, -1.0, 1.0);
  // The turn so far, unwrapped step by step: "cw 360" is a whole turn, not none.
  turned_rad_ += std::remainder(now.yaw_rad - last_yaw_rad_, 2.0 * std::numbers::pi);
  last_yaw_rad_ = now.yaw_rad;
  const double yaw_error = plan_.turn_rad - turned_rad_;
  const double yaw_rate = std::clamp(kTurnGainPerS * yaw_error, -kTurnRateRadps, kTurnRateRadps);
  command.yaw_rate = std::clamp(yaw_rate / kMaxTurnRadps, -1.0, 1.0);
  const bool reached = last && error_world.norm() < kReachedM && now.velocity_body_mps.norm() < kSettledMps &&
                       std::abs(yaw_error) < kTurnedRad;
  return reached ? Status::Done : Status::Flying;
}

}  // namespace labo::tello
