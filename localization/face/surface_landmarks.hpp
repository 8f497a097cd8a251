#pragma once
// Where a person's landmarks lie on their own face surface. The iBUG-68 mapping names one CANDIDE-3
// vertex (or a blend of a few) per landmark, but the landmark detector puts, say, a brow end or the
// nose's lower end at a point of the person's face that is seldom exactly that vertex; in depth the
// difference is not seen in a frontal picture and shows as a pitch and distance bias (docs/face.md).
// At registration the ray through each detected landmark of the frontal picture is cut with the
// fitted mesh: the hit is the landmark's point on that face. Kept as an offset from the mapped point.
#include <Eigen/Geometry>

#include "core/candide3.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

// 3 x n offsets (metres, face frame) from model.points_m(tau, ipd_m) to where the rays through
// `ideal_pixels` (2 x n, the model's landmarks in the registration picture) first hit the fitted
// CANDIDE-3 mesh at `T_cam_face`. A landmark whose ray misses the mesh, or hits farther than
// `max_offset_m` from its mapped point, keeps a zero offset.
Eigen::Matrix3Xd surface_landmark_offsets(const Candide3Model& candide, const FaceLandmarkModel& model,
                                          const Eigen::VectorXd& tau, double ipd_m, const Eigen::Isometry3d& T_cam_face,
                                          const Eigen::Matrix2Xd& ideal_pixels, const IdealPinhole& camera,
                                          double max_offset_m);

}  // namespace labo::face
