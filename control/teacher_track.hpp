#pragma once
// TeacherTrack: what face-follow keeps of the teacher between face results, from the face's world
// poses alone: where the face is, how fast and which way it moves, and which way the teacher's body
// faces. Nothing else tells it where the teacher goes: their walk, its speed and its pauses are
// measured from the faces, never given.
//
// The velocity is the face's displacement between results, low-passed (kVelocityTauS): a 2 cm depth
// jitter is 0.6 m/s between two frames at 30 fps, a walk is a steady drift of 0.3-0.7 m/s.
// Why the body's heading and not the face's: the head sways (±35° about the walking direction in the
// simulated lab, people look around), and a standoff on the head's instantaneous line of sight swings
// the drone sideways by d·sin(sway) (0.57 m at 1 m). While the teacher walks forwards (the walking
// direction within kForwardWalkRad of where the face looks), the walking direction is their heading;
// standing (turning on the spot), the face's heading is all there is: a turn beyond the sway is
// followed at once, the sway itself only slowly.
#include <Eigen/Geometry>

#include "core/time.hpp"

namespace labo::control {

class TeacherTrack {
 public:
  // Start from one face pose (control's convention: z into the face).
  void reset(const Eigen::Isometry3d& T_world_face, Seconds t);
  // Fold in the next face pose (t after the previous one).
  void update(const Eigen::Isometry3d& T_world_face, Seconds t);
  // Fold in the next place of the teacher's head without a face (turned or walking away): the
  // heading stays. Taking a teacher who walks away to look where they walk sent the drone round them
  // to their front, across their path: it flew into the teacher's head (seed 1000, tuning).
  void update_position(const Eigen::Vector3d& position, Seconds t);
  // Move the track along its motion (face lost: where it most likely went); the turn rate decays.
  void coast(Seconds dt);
  // The drone's pose estimate was corrected by `by` (world), beyond what its velocity explains: the
  // faces placed from it move by as much, and that is no walk of the teacher. Moves the track with it,
  // so the next face's displacement is measured in the corrected frame.
  void shift(const Eigen::Vector3d& by) { position_ += by; }
  // The teacher is taken to stand (a coast has run its course: how far a lost teacher walked on is
  // not known, and the drone must not fly after a guess).
  void stop() { velocity_.setZero(); }

  const Eigen::Vector3d& position() const { return position_; }
  const Eigen::Vector3d& velocity() const { return velocity_; }  // horizontal
  double heading() const { return heading_; }                   // the body's facing direction (rad, world)
  double heading_rate() const { return heading_rate_; }         // rad/s
  bool walking() const { return velocity_.norm() > kWalkingMps; }
  // An upright face at position() facing `heading_rad` (control's convention: z into the face).
  Eigen::Isometry3d T_world_upright_face(double heading_rad) const;

  static constexpr double kWalkingMps = 0.2;

 private:
  // How far the heading moves towards the body's this update, the face looking at `looking`.
  double heading_step(double looking, double dt) const;
  // Moves the place and velocity to the next measurement; the time since the last one.
  double move_to(const Eigen::Vector3d& position, Seconds t);
  void turn(double step, double dt);

  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  double heading_ = 0;
  double heading_rate_ = 0;
  Seconds t_ = 0;
};

// Where a face (control's convention, z into the face) looks, as a world heading.
double facing_heading(const Eigen::Isometry3d& T_world_face);
// An upright face at `position` looking towards world heading `heading_rad` (z into the face).
Eigen::Isometry3d upright_face_pose(const Eigen::Vector3d& position, double heading_rad);

}  // namespace labo::control
