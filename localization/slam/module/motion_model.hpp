#pragma once
// MotionModel: the tracker's pose prior when the caller gives none. PTAM's decaying constant
// velocity: the last frame-to-frame motion, scaled to the new frame's interval and damped (0.9),
// applied to the last pose. Poses are T_cam_map; the model holds the last two accepted ones.
#include <Eigen/Geometry>
#include <optional>

#include "core/time.hpp"
#include "localization/slam/optimize/sim3.hpp"

namespace labo::slam {

class MotionModel {
 public:
  // Both poses known (a new map: its two keyframes).
  void start(const Eigen::Isometry3d& previous_T, Seconds previous_t, const Eigen::Isometry3d& last_T, Seconds last_t);
  void accept(const Eigen::Isometry3d& T, Seconds t);
  // A relocalized pose has no velocity: the next prior is the pose itself.
  void forget_velocity() { previous_T_.reset(); }
  void clear();
  // The map moved under the poses (a loop correction): pose' = rigid part of (pose * G_inv).
  void follow(const Similarity3& G_inv);

  const std::optional<Eigen::Isometry3d>& last() const { return last_T_; }
  // The motion expected from the last pose to a frame at t (pose at t = step * last), when the model
  // has a velocity; at most three times the last interval's motion.
  std::optional<Eigen::Isometry3d> step_to(Seconds t) const;

 private:
  std::optional<Eigen::Isometry3d> last_T_, previous_T_;
  Seconds last_t_ = 0, previous_t_ = 0;
};

}  // namespace labo::slam
