#pragma once
// Landmark: the world pose of something the camera localizes (an instrument, the landing platform,
// the teacher's face) with a scalar position variance. Placed at its first sighting by cascading
// T_world_body * T_body_cam * T_cam_landmark, optionally fused with a surveyed pose, and refined by
// later sightings with the weights of a scalar Kalman filter.
#include <Eigen/Geometry>

#include "core/time.hpp"

namespace labo {

struct Landmark {
  Eigen::Isometry3d T_world_landmark = Eigen::Isometry3d::Identity();
  double position_var = 0;  // m^2, isotropic
  int refinements = 0;
  Seconds last_seen = 0;

  // Moves toward a measured pose with weight k in [0, 1] (translation linearly, rotation by slerp).
  void blend(const Eigen::Isometry3d& T_measured, double k);
  // Fuses a measurement of variance `var` (Kalman weight var_self / (var_self + var)).
  void fuse(const Eigen::Isometry3d& T_measured, double var);
};

// Combines a cascade (its variance) with a survey (its variance) into a first placement.
Landmark place_landmark(const Eigen::Isometry3d& T_cascade, double cascade_var,
                        const Eigen::Isometry3d* T_surveyed, double survey_var, Seconds t);

}  // namespace labo
