#pragma once
// Where a person's landmarks lie on their own face surface. The iBUG-68 mapping names one CANDIDE-3
// vertex (or a blend of a few) per landmark, but the landmark detector puts, say, a brow end or the
// nose's lower end at a point of the person's face that is seldom exactly that vertex; in depth the
// difference is not seen in a frontal picture and shows as a pitch and distance bias (docs/face.md).
// In the image plane the difference is seen in the registration picture (the fit leaves ~3 px RMS):
// at registration the ray through each detected landmark of the frontal picture is followed to the
// mapped point's depth, and that point (the picture's in-plane position, the model's depth) is the
// person's landmark, provided the ray hits the fitted mesh. Kept as an offset from the mapped point.
#include <Eigen/Geometry>

#include "core/candide3.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

// 3 x n offsets (metres, face frame, z = 0 before the scaling below) from model.points_m(tau, ipd_m)
// to where the rays through `ideal_pixels` (2 x n, the model's landmarks in the registration picture,
// camera at `T_cam_face`) cross the mapped points' depth planes. A landmark whose ray misses the fitted
// CANDIDE-3 mesh, or whose crossing lies farther than `max_offset_m` from its mapped point, keeps a
// zero offset. The moved points are then scaled about the face origin so that the eye centres keep
// the mapped points' distance (the interpupillary distance stays the metric scale).
Eigen::Matrix3Xd surface_landmark_offsets(const Candide3Model& candide, const FaceLandmarkModel& model,
                                          const Eigen::VectorXd& tau, double ipd_m, const Eigen::Isometry3d& T_cam_face,
                                          const Eigen::Matrix2Xd& ideal_pixels, const IdealPinhole& camera,
                                          double max_offset_m);

}  // namespace labo::face
