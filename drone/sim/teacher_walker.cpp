#include "drone/sim/teacher_walker.hpp"

#include <algorithm>
#include <cmath>

#include "drone/sim/teacher_walk.hpp"

namespace labo::sim {

using lab::LabDescription;
using lab::TeacherSpec;


namespace {
// A teacher giving way walks on once the drone is this much farther than keep_clear_m (it hovers
// and jitters at the edge: no stop-and-go at 30 Hz).
constexpr double kResumeMarginM = 0.1;
constexpr double kSideStepMps = 0.5;  // stepping aside
constexpr double kDriftBackMps = 0.2;  // back onto the path, walking
constexpr double kPassingM = 1.5;      // ... once the drone is behind or this far
// A side step keeps this clear of walls and objects (less than the drawn walk's clearance: a step
// aside is brief).
constexpr double kSideStepClearanceM = 0.1;
}  // namespace

TeacherWalker::TeacherWalker(const TeacherSpec& spec)
    : motion_(spec), give_way_(spec.give_way), body_radius_m_(spec.body_radius_m), pose_(motion_.pose(0.0)) {}

bool TeacherWalker::in_the_way(const TeacherPose& on_path, const Eigen::Vector3d& drone) const {
  if (!on_path.walking) return false;
  const Eigen::Vector2d along(std::cos(on_path.heading_rad), std::sin(on_path.heading_rad));
  const Eigen::Vector2d to_drone = drone.head<2>() - (on_path.floor_xy + offset_);
  const double ahead = to_drone.dot(along);
  const double aside = std::abs(along.x() * to_drone.y() - along.y() * to_drone.x());
  const double margin = giving_way_ ? kResumeMarginM : 0.0;
  return ahead > 0 && ahead - body_radius_m_ < give_way_.keep_clear_m + margin && aside < body_radius_m_ + kCorridorMarginM + margin;
}

void TeacherWalker::step_aside(const TeacherPose& on_path, const Eigen::Vector3d& drone, double dt, const LabDescription& lab) {
  const Eigen::Vector2d along(std::cos(on_path.heading_rad), std::sin(on_path.heading_rad));
  const Eigen::Vector2d left(-along.y(), along.x());
  const Eigen::Vector2d to_drone = drone.head<2>() - (on_path.floor_xy + offset_);
  const Eigen::Vector2d away = to_drone.dot(left) > 0 ? Eigen::Vector2d(-left) : left;
  const Eigen::Vector2d target = give_way_.side_step_m * away;
  const Eigen::Vector2d to_target = target - offset_;
  const double reach = kSideStepMps * dt;
  const Eigen::Vector2d next = to_target.norm() > reach ? Eigen::Vector2d(offset_ + reach * to_target.normalized()) : target;
  if (on_free_floor(lab, on_path.floor_xy + next, body_radius_m_, kSideStepClearanceM, kSideStepClearanceM)) offset_ = next;
}

bool TeacherWalker::passing(const TeacherPose& on_path, const Eigen::Vector3d& drone) const {
  const Eigen::Vector2d along(std::cos(on_path.heading_rad), std::sin(on_path.heading_rad));
  const Eigen::Vector2d to_drone = drone.head<2>() - (on_path.floor_xy + offset_);
  return to_drone.dot(along) > -body_radius_m_ - kCorridorMarginM && to_drone.norm() < kPassingM;
}

void TeacherWalker::advance(Seconds t, const Eigen::Vector3d& drone, const LabDescription& lab) {
  const double dt = std::max(0.0, t - t_);
  t_ = std::max(t_, t);
  const TeacherPose on_path = motion_.pose(walk_t_, t_);
  giving_way_ = in_the_way(on_path, drone);
  if (giving_way_) {
    if (give_way_.side_step_m > 0) step_aside(on_path, drone, dt, lab);
  } else {
    walk_t_ += dt;
    // Back onto the path once past the drone, not while walking by it.
    const double back = passing(on_path, drone) ? 0.0 : kDriftBackMps * dt;
    offset_ = offset_.norm() > back ? Eigen::Vector2d(offset_ - back * offset_.normalized()) : Eigen::Vector2d::Zero();
  }
  pose_ = place(t_);
}

TeacherPose TeacherWalker::place(Seconds head_t) const {
  TeacherPose p = motion_.pose(walk_t_, head_t);
  p.floor_xy += offset_;
  p.T_world_head.translation().head<2>() += offset_;
  p.walking = p.walking && !giving_way_;
  return p;
}

}  // namespace labo::sim
