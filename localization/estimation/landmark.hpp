#pragma once
// Landmark: the world pose of something the camera localizes (an instrument, the landing platform,
// the teacher's face) with a scalar position variance and a scalar rotation variance. Placed at its
// first sighting by cascading T_world_body * T_body_cam * T_cam_landmark, optionally fused with a
// surveyed pose, and refined by later sightings with the weights of a scalar Kalman filter: the
// position by the position variances, the orientation by the rotation variances: with one weight for
// both, a planar panel's orientation seen from 4 m (off by up to ~20 degrees) would turn a placement
// whose survey was right. Test "estimation: an object's placement weighs orientations by their
// rotation variances".
#include <Eigen/Geometry>

#include "core/time.hpp"

namespace labo::estimation {

// A pose measurement with its isotropic variances (m^2 for the position, rad^2 for the rotation).
struct PoseWithVariance {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  double position_var = 0;
  double rotation_var = 0;
};

struct Landmark {
  Eigen::Isometry3d T_world_landmark = Eigen::Isometry3d::Identity();
  double position_var = 0;  // m^2, isotropic
  double rotation_var = 0;  // rad^2, isotropic
  int refinements = 0;
  Seconds last_seen = 0;

  // Moves toward a measured pose with weight k in [0, 1] (translation linearly, rotation by slerp).
  void blend(const Eigen::Isometry3d& T_measured, double k);
  // Fuses a measurement: the position with the Kalman weight var_self / (var_self + var), the rotation
  // with the same weight of the rotation variances.
  void fuse(const PoseWithVariance& measured);
};

// Combines a cascade with a survey (each with its variances) into a first placement.
Landmark place_landmark(const PoseWithVariance& cascade, const PoseWithVariance* surveyed, Seconds t);

}  // namespace labo::estimation
