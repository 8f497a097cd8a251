#pragma once
// The part of the pose estimate's displacement between two ticks that its own velocity does not
// explain: a correction of the estimate (a fix of a landmark, the handling of a velocity dropout),
// not a motion of the drone. Whatever a mission placed in the world from the estimate (a face, the
// platform as the bottom camera saw it) moved with the estimate's frame and is moved by as much:
// kept where it was, it would be that far off in the corrected frame.
#include <Eigen/Core>

#include "localization/fusion/localization_pipelines.hpp"

namespace labo::control {

class EstimateCorrection {
 public:
  // The correction since the last call: zero on the first call, after an invalid estimate, and when
  // time did not advance.
  Eigen::Vector3d update(const fusion::PoseEstimate& pose, Seconds t);

 private:
  bool have_last_ = false;
  Seconds last_t_ = 0;
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace labo::control
