#include "drone/sim/teacher_walk.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/frames.hpp"
#include "drone/sim/seeded_draw.hpp"

namespace labo::sim {

using lab::LabDescription;
using lab::TeacherSpec;


namespace {

constexpr int kTriesPerLeg = 400;
constexpr double kSegmentStepM = 0.1;

// The walk's draws: its own stream, apart from the world's other draws and the sensors' noise.
constexpr std::uint32_t kWalkStream = 0x7465616cu;

bool segment_on_free_floor(const LabDescription& lab, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double r,
                           const TeacherWalkRanges& ranges) {
  const int steps = 1 + static_cast<int>((b - a).norm() / kSegmentStepM);
  for (int k = 0; k <= steps; ++k)
    if (!on_free_floor(lab, a + (b - a) * (static_cast<double>(k) / steps), r, ranges.wall_clearance_m, ranges.object_clearance_m))
      return false;
  return true;
}

}  // namespace

bool on_free_floor(const LabDescription& lab, const Eigen::Vector2d& xy, double body_radius_m, double wall_clearance_m,
                   double object_clearance_m) {
  const double wall = body_radius_m + wall_clearance_m;
  if ((xy.array() < lab.room.min.head<2>().array() + wall).any() || (xy.array() > lab.room.max.head<2>().array() - wall).any())
    return false;
  // Probed on a 5x5 grid over the square the body and its clearance cover: the objects are far larger.
  const double reach = body_radius_m + object_clearance_m;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      if (lab.surface_height(xy.x() + 0.5 * i * reach, xy.y() + 0.5 * j * reach) > lab.room.min.z() + 1e-6) return false;
  return true;
}

TeacherSpec random_teacher_walk(const LabDescription& lab, std::uint64_t seed, const TeacherWalkRanges& ranges) {
  TeacherSpec walk = lab.teacher;
  const double r = walk.body_radius_m;
  SeededDraw d(seed, kWalkStream);
  const Eigen::Vector2d lo = lab.room.min.head<2>(), hi = lab.room.max.head<2>();
  const auto any_point = [&] { return Eigen::Vector2d(d.in(lo.x(), hi.x()), d.in(lo.y(), hi.y())); };
  Eigen::Vector2d at = any_point();
  for (int tries = 0; !on_free_floor(lab, at, r, ranges.wall_clearance_m, ranges.object_clearance_m); at = any_point())
    if (++tries > 100 * kTriesPerLeg) throw std::runtime_error(lab.source.string() + ": no free floor for the teacher to walk on");
  walk.speed_mps = d.in(ranges.min_speed_mps, ranges.max_speed_mps);
  walk.head.yaw_amplitude_deg = d.in(ranges.min_head_yaw_deg, ranges.max_head_yaw_deg);
  walk.head.yaw_period_s = d.in(ranges.min_head_yaw_period_s, ranges.max_head_yaw_period_s);
  walk.loop = false;
  walk.waypoints = {at};
  walk.pauses_s = {d.in(ranges.min_stand_s, ranges.max_stand_s)};
  double heading = d.in(-std::numbers::pi, std::numbers::pi);
  for (double t = 0; t < ranges.horizon_s;) {
    Eigen::Vector2d next = at;
    for (int k = 0; k < kTriesPerLeg && next == at; ++k) {
      const double a = d.in(-std::numbers::pi, std::numbers::pi), length = d.in(ranges.min_leg_m, ranges.max_leg_m);
      const Eigen::Vector2d to = at + length * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (segment_on_free_floor(lab, at, to, r, ranges)) next = to;
    }
    if (next == at) break;  // boxed in: the walk ends here
    const double out = std::atan2(next.y() - at.y(), next.x() - at.x());
    // The pause before this leg: turning towards it, then standing.
    walk.pauses_s.back() += std::abs(wrap_angle(out - heading)) / ranges.turn_radps;
    t += walk.pauses_s.back() + (next - at).norm() / walk.speed_mps;
    walk.waypoints.push_back(next);
    walk.pauses_s.push_back(d.in(ranges.min_stand_s, ranges.max_stand_s));
    heading = out;
    at = next;
  }
  // Drawn after the legs: the walk itself stays what it was drawn as before these were.
  walk.give_way.keep_clear_m = d.in(ranges.min_keep_clear_m, ranges.max_keep_clear_m);
  const bool side_steps = d.in(0.0, 1.0) < ranges.side_step_share;
  const double side_step_m = d.in(ranges.min_side_step_m, ranges.max_side_step_m);
  walk.give_way.side_step_m = side_steps ? side_step_m : 0.0;
  return walk;
}

}  // namespace labo::sim
