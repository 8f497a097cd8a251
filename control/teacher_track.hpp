#pragma once
// TeacherTrack: what face-follow keeps of the teacher between face results: where the face is, how
// fast it moves, and which way the teacher's body faces, from the face's world poses.
//
// Why the body's heading and not the face's: the head sways (±35° about the walking direction in the
// simulated lab, people look around), and a standoff on the head's instantaneous line of sight swings
// the drone sideways by d·sin(sway) (0.57 m at 1 m). While the teacher walks forwards (the walking
// direction within kForwardWalkRad of where the face looks), the walking direction is their heading;
// standing (turning at a corner), the face's heading is all there is and is followed.
#include <Eigen/Geometry>

#include "core/time.hpp"

namespace labo::control {

class TeacherTrack {
 public:
  // Start from one face pose (control's convention: z into the face).
  void reset(const Eigen::Isometry3d& T_world_face, Seconds t);
  // Fold in the next face pose (t after the previous one).
  void update(const Eigen::Isometry3d& T_world_face, Seconds t);
  // Take the face up again after a gap: its place now, keeping the heading and the velocity the track
  // had (placed from the route: the leg they walk, or are about to walk: then the heading stays until
  // they walk).
  void resume(const Eigen::Isometry3d& T_world_face, Seconds t);
  // Move the track along its motion (face lost: where it most likely went); the turn rate decays.
  void coast(Seconds dt);
  // The drone's pose estimate was corrected by `by` (world), beyond what its velocity explains: the
  // faces placed from it move by as much, and that is no walk of the teacher. Moves the track with it,
  // so the next face's displacement is measured in the corrected frame.
  void shift(const Eigen::Vector3d& by) {
    position_ += by;
    walk_.at += by.head<2>();
    last_walk_.at += by.head<2>();
  }
  // Pretend the teacher is at `xy` facing `heading_rad`, moving at `velocity` (a prediction from the
  // route).
  void place(const Eigen::Vector2d& xy, double heading_rad, const Eigen::Vector2d& velocity = Eigen::Vector2d::Zero());
  // The route has the teacher walking at `velocity` now (set off from a corner at the route's time)
  // while the face may not show it yet: the track moves at least that fast along it.
  void expect_walk(const Eigen::Vector2d& velocity);
  // ... and the route was early: they still stand.
  void stand() { velocity_.setZero(); }

  // The last sustained spell of walking seen (kSustainedWalkS or longer; may still go on): when it
  // started and last walked, and which way. A teacher stopping at a corner of a known route after one
  // is arriving there (they pause, then set off along the next leg); a short spell is the face pose's
  // jitter as likely as a step.
  struct WalkSpell {
    bool seen = false;
    Seconds from = 0, to = 0;
    Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
    Eigen::Vector2d at = Eigen::Vector2d::Zero();  // where the track was at `to`
  };
  const WalkSpell& last_walk() const { return last_walk_; }

  const Eigen::Vector3d& position() const { return position_; }
  const Eigen::Vector3d& velocity() const { return velocity_; }  // horizontal
  double heading() const { return heading_; }                   // the body's facing direction (rad, world)
  double heading_rate() const { return heading_rate_; }         // rad/s
  bool walking() const { return velocity_.norm() > kWalkingMps; }
  // An upright face at position() facing `heading_rad` (control's convention: z into the face).
  Eigen::Isometry3d T_world_upright_face(double heading_rad) const;

  static constexpr double kWalkingMps = 0.2;
  static constexpr double kSustainedWalkS = 0.7;

 private:
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  double heading_ = 0;
  double heading_rate_ = 0;
  bool hold_heading_ = false;  // resumed: the heading stays until the teacher walks
  Seconds t_ = 0;
  WalkSpell walk_;       // the current (or last) spell of walking, sustained or not
  WalkSpell last_walk_;  // the last sustained one
  void note_walking(Seconds t);
};

// Where a face (control's convention, z into the face) looks, as a world heading.
double facing_heading(const Eigen::Isometry3d& T_world_face);

}  // namespace labo::control
