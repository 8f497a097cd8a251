#include "drone/sim/teacher_motion.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/frames.hpp"

namespace labo::sim {

using lab::HeadMotionSpec;
using lab::TeacherSpec;


namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

double sinusoid(double amplitude_deg, Seconds period_s, Seconds t) {
  if (period_s <= 0) return 0.0;
  return amplitude_deg * kDegToRad * std::sin(2.0 * std::numbers::pi * t / period_s);
}

// The face frame of someone standing upright and facing `heading` (world): +z along the heading,
// +y up, +x to their left.
Eigen::Matrix3d upright_face(double heading) {
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
  R.col(1) = Eigen::Vector3d::UnitZ();
  R.col(2) = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
  return R;
}

}  // namespace

TeacherMotion::TeacherMotion(const TeacherSpec& spec) : spec_(spec) {
  if (spec_.waypoints.empty()) throw std::invalid_argument("the teacher's path has no waypoint");
  if (!(spec_.speed_mps > 0)) throw std::invalid_argument("the teacher's speed must be positive");
  const std::size_t n = spec_.waypoints.size();
  if (!spec_.pauses_s.empty() && spec_.pauses_s.size() != n)
    throw std::invalid_argument("the teacher's path has " + std::to_string(spec_.pauses_s.size()) + " pauses for " +
                                std::to_string(n) + " waypoints (one each expected)");
  // A looped path walks back from the last waypoint to the first; an open one ends standing at the
  // last (a leg of zero length, its pause lasting for ever).
  Seconds t = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Leg leg;
    leg.from = spec_.waypoints[i];
    const bool last = i + 1 == n;
    leg.to = last && !spec_.loop ? leg.from : spec_.waypoints[(i + 1) % n];
    const Eigen::Vector2d d = leg.to - leg.from;
    leg.heading_out = d.norm() > 1e-9 ? std::atan2(d.y(), d.x()) : (i > 0 ? legs_.back().heading_out : 0.0);
    leg.pause_start = t;
    leg.walk_start = t + std::max(0.0, spec_.pauses_s.empty() ? spec_.pause_s : spec_.pauses_s[i]);
    leg.walk_end = leg.walk_start + d.norm() / spec_.speed_mps;
    t = leg.walk_end;
    legs_.push_back(leg);
  }
  for (std::size_t i = 0; i < n; ++i) legs_[i].heading_in = legs_[(i + n - 1) % n].heading_out;
  if (!spec_.loop) legs_.front().heading_in = legs_.front().heading_out;
  cycle_s_ = t;
}

TeacherPose TeacherMotion::pose(Seconds walk_t, Seconds head_t) const {
  const Seconds tau = !spec_.loop ? std::max(0.0, walk_t) : cycle_s_ > 0 ? std::fmod(std::max(0.0, walk_t), cycle_s_) : 0.0;
  const Leg* leg = &legs_.back();
  for (const Leg& l : legs_) {
    if (tau < l.walk_end) {
      leg = &l;
      break;
    }
  }
  TeacherPose p;
  if (!spec_.loop && tau >= legs_.back().walk_start) {
    // The walk is over: standing at its last waypoint, facing the way they came.
    p.floor_xy = legs_.back().from;
    p.heading_rad = legs_.back().heading_in;
  } else if (tau < leg->walk_start) {
    // Standing: turn smoothly from the incoming to the outgoing direction.
    const double f = leg->walk_start > leg->pause_start ? (tau - leg->pause_start) / (leg->walk_start - leg->pause_start) : 1.0;
    const double s = f * f * (3.0 - 2.0 * f);
    p.floor_xy = leg->from;
    p.heading_rad = wrap_angle(leg->heading_in + s * wrap_angle(leg->heading_out - leg->heading_in));
  } else {
    const double f = (tau - leg->walk_start) / std::max(1e-9, leg->walk_end - leg->walk_start);
    p.floor_xy = leg->from + f * (leg->to - leg->from);
    p.heading_rad = leg->heading_out;
    p.walking = true;
  }
  const HeadMotionSpec& h = spec_.head;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(sinusoid(h.yaw_amplitude_deg, h.yaw_period_s, head_t), Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(sinusoid(h.pitch_amplitude_deg, h.pitch_period_s, head_t), Eigen::Vector3d::UnitX()) *
      Eigen::AngleAxisd(sinusoid(h.roll_amplitude_deg, h.roll_period_s, head_t), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.T_world_head.linear() = upright_face(p.heading_rad) * turn;
  p.T_world_head.translation() = Eigen::Vector3d(p.floor_xy.x(), p.floor_xy.y(), spec_.eye_height_m);
  return p;
}

}  // namespace labo::sim
