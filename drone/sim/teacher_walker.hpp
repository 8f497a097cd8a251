#pragma once
// TeacherWalker: the simulated lab's teacher walking their path (TeacherMotion) and keeping out of
// the drone's way as a person would (GiveWaySpec in lab_description.hpp): walking, with the drone's
// centre in the corridor their body sweeps (the body's radius and kCorridorMarginM either side of
// the walking line) and within keep_clear_m ahead of the body's front, they stop; the path's clock
// waits while the head keeps turning. A teacher who side-steps also moves aside, away from the
// drone, by up to side_step_m where the floor stays free (on_free_floor), walks on past it from
// there, and drifts back onto the path afterwards. Stepping state, advanced with the simulation's
// time: nothing of it reaches the flight software, which sees the teacher only through the cameras.
#include <Eigen/Core>

#include "core/time.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/teacher_motion.hpp"

namespace labo::sim {

class TeacherWalker {
 public:
  static constexpr double kCorridorMarginM = 0.3;  // about the drone's hull radius

  explicit TeacherWalker(const lab::TeacherSpec& spec);
  // Walks on to time `t` (not before the last call), the drone's centre at `drone` (world); `lab`
  // tells where a side step may go.
  void advance(Seconds t, const Eigen::Vector3d& drone, const lab::LabDescription& lab);
  const TeacherPose& pose() const { return pose_; }
  bool giving_way() const { return giving_way_; }
  // How far aside of the path the teacher stands now (m).
  double aside_m() const { return offset_.norm(); }

 private:
  bool in_the_way(const TeacherPose& on_path, const Eigen::Vector3d& drone) const;
  // Walking by the drone (it is beside or ahead of them, near): a side step is kept meanwhile.
  bool passing(const TeacherPose& on_path, const Eigen::Vector3d& drone) const;
  void step_aside(const TeacherPose& on_path, const Eigen::Vector3d& drone, double dt, const lab::LabDescription& lab);
  TeacherPose place(Seconds head_t) const;

  TeacherMotion motion_;
  lab::GiveWaySpec give_way_;
  double body_radius_m_;
  Seconds t_ = 0;
  Seconds walk_t_ = 0;  // the path's own time: it stands still while the teacher gives way
  Eigen::Vector2d offset_ = Eigen::Vector2d::Zero();  // the side step, from the path
  bool giving_way_ = false;
  TeacherPose pose_;
};

}  // namespace labo::sim
