#include "localization/slam/module/motion_model.hpp"

#include <algorithm>

#include "localization/slam/optimize/se3.hpp"

namespace labo::slam {

void MotionModel::start(const Eigen::Isometry3d& previous_T, Seconds previous_t, const Eigen::Isometry3d& last_T,
                        Seconds last_t) {
  last_T_ = last_T;
  last_t_ = last_t;
  previous_T_ = previous_T;
  previous_t_ = previous_t;
}

void MotionModel::accept(const Eigen::Isometry3d& T, Seconds t) {
  previous_T_ = last_T_;
  previous_t_ = last_t_;
  last_T_ = T;
  last_t_ = t;
}

void MotionModel::clear() {
  last_T_.reset();
  previous_T_.reset();
}

void MotionModel::follow(const Similarity3& G_inv) {
  if (last_T_) last_T_ = (Similarity3::from_rigid(*last_T_) * G_inv).rigid_pose();
  if (previous_T_) previous_T_ = (Similarity3::from_rigid(*previous_T_) * G_inv).rigid_pose();
}

std::optional<Eigen::Isometry3d> MotionModel::step_to(Seconds t) const {
  if (!last_T_ || !previous_T_ || !(last_t_ > previous_t_)) return std::nullopt;
  const Eigen::Isometry3d delta = *last_T_ * previous_T_->inverse();
  const double fraction = 0.9 * (t - last_t_) / (last_t_ - previous_t_);
  return scale_motion(delta, std::min(fraction, 3.0));
}

}  // namespace labo::slam
