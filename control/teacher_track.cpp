#include "control/teacher_track.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/frames.hpp"

namespace labo::control {

namespace {
// Time constants of the low-passes (s). The face's place follows quickly (the standoff must not
// lag a walking teacher); its velocity and heading average the pose's frame-to-frame noise (a 2 cm
// depth jitter is 0.6 m/s between two frames at 30 fps).
constexpr double kPositionTauS = 0.05;
constexpr double kVelocityTauS = 0.4;
constexpr double kHeadingTauS = 0.6;
constexpr double kHeadingRateTauS = 0.5;
constexpr double kCoastRateDecayS = 1.0;
// Walking forwards: the walking direction within this of where the face looks.
constexpr double kForwardWalkRad = std::numbers::pi / 3;
// Standing, the head sways about the body's heading (people look around, +-20-40 degrees): a face
// looking within kStandingSwayRad of the heading moves it only slowly (kStandingHeadingTauS, longer
// than a sway's half period), a face looking farther moves it by the excess at kHeadingTauS (the
// teacher turned). Following every glance swings the drone 0.5-0.8 m sideways at 1 m, and leaves
// it off the teacher's line when they set off (tests "control: a standing teacher's swaying head
// does not swing the heading" and "control: a correction of the drone's pose estimate is not taken
// for the teacher's walk").
constexpr double kStandingSwayRad = 0.4;
constexpr double kStandingHeadingTauS = 4.0;

double blend(double dt, double tau) { return 1.0 - std::exp(-dt / tau); }
}  // namespace

double facing_heading(const Eigen::Isometry3d& T_world_face) {
  const Eigen::Vector3d out = -T_world_face.linear().col(2);  // z is into the face
  return std::atan2(out.y(), out.x());
}

void TeacherTrack::reset(const Eigen::Isometry3d& T_world_face, Seconds t) {
  position_ = T_world_face.translation();
  velocity_.setZero();
  heading_ = facing_heading(T_world_face);
  heading_rate_ = 0;
  t_ = t;
}

double TeacherTrack::move_to(const Eigen::Vector3d& position, Seconds t) {
  const double dt = std::max(t - t_, 1e-3);
  t_ = t;
  const Eigen::Vector3d previous = position_;
  position_ += blend(dt, kPositionTauS) * (position - position_);
  Eigen::Vector3d v = (position_ - previous) / dt;
  v.z() = 0;
  velocity_ += blend(dt, kVelocityTauS) * (v - velocity_);
  return dt;
}

void TeacherTrack::turn(double step, double dt) {
  heading_ = wrap_angle(heading_ + step);
  heading_rate_ += blend(dt, kHeadingRateTauS) * (step / dt - heading_rate_);
}

void TeacherTrack::update(const Eigen::Isometry3d& T_world_face, Seconds t) {
  const double dt = move_to(T_world_face.translation(), t);
  turn(heading_step(facing_heading(T_world_face), dt), dt);
}

void TeacherTrack::update_position(const Eigen::Vector3d& position, Seconds t) {
  const double dt = move_to(position, t);
  turn(0.0, dt);
}

double TeacherTrack::heading_step(double looking, double dt) const {
  if (walking()) {
    const double walking_heading = std::atan2(velocity_.y(), velocity_.x());
    if (std::abs(wrap_angle(walking_heading - looking)) < kForwardWalkRad)
      return blend(dt, kHeadingTauS) * wrap_angle(walking_heading - heading_);
  }
  const double off = wrap_angle(looking - heading_);
  const double excess = off - std::clamp(off, -kStandingSwayRad, kStandingSwayRad);
  return blend(dt, kHeadingTauS) * excess + blend(dt, kStandingHeadingTauS) * (off - excess);
}

void TeacherTrack::coast(Seconds dt) {
  position_ += velocity_ * dt;
  heading_ = wrap_angle(heading_ + heading_rate_ * dt);
  heading_rate_ *= std::exp(-dt / kCoastRateDecayS);
  t_ += dt;
}

Eigen::Isometry3d upright_face_pose(const Eigen::Vector3d& position, double heading_rad) {
  const Eigen::Vector3d into(-std::cos(heading_rad), -std::sin(heading_rad), 0.0);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // z into the face, y up, x = y cross z (standoff_target() reads z only).
  T.linear().col(2) = into;
  T.linear().col(1) = up;
  T.linear().col(0) = up.cross(into);
  T.translation() = position;
  return T;
}

Eigen::Isometry3d TeacherTrack::T_world_upright_face(double heading_rad) const { return upright_face_pose(position_, heading_rad); }

}  // namespace labo::control
