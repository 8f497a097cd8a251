#pragma once
// HeadRange: where a followed head is, its distance fixed by the teacher's face height. The head
// tracker (face::HeadTracker) gives a ray to the head and a distance from its patch's scale, and that
// scale drifts while the face is not posed (tuning seed 1002: 1.3 m read with the teacher 0.3-0.6 m
// away). The height the teacher's face is carried at hardly changes while they stand or walk, and the
// posed faces measure it; a drone flying over their head (face_blind_altitude_m) sees the head below
// its camera, and the ray's slope then gives the distance from that height: the nearer the head, the
// steeper the ray and the surer the distance, where a wrong one is most dangerous. The two distances
// are weighed by their uncertainties; at the face's own height the ray is level and the scale's is kept.
#include <Eigen/Core>

#include "core/time.hpp"

namespace labo::control {

class HeadRange {
 public:
  // A posed face's place in the world: its height is learnt (a running mean whose newest face
  // weighs 1/30 once 30 are in).
  void learn(const Eigen::Vector3d& face_world);
  bool knows_height() const { return faces_ > 0; }
  double face_height_m() const { return face_z_m_; }

  // The head seen at `head_world` (from its patch's scale) by a camera at `camera_world`,
  // `since_posed_s` after the last posed face: the place on the same ray at the distance both cues
  // give together. Unchanged before a face was posed, or when the ray is level.
  Eigen::Vector3d place(const Eigen::Vector3d& camera_world, const Eigen::Vector3d& head_world, Seconds since_posed_s) const;

 private:
  double face_z_m_ = 0;
  int faces_ = 0;
};

}  // namespace labo::control
