#pragma once
// Where a person's landmarks lie on their own face surface. The iBUG-68 mapping names one CANDIDE-3
// vertex (or a blend of a few) per landmark, but the landmark detector puts, say, a brow end or the
// nose's lower end at a point of the person's face that is seldom exactly that vertex; in depth the
// difference is not seen in a frontal picture and shows as a pitch and distance bias (docs/face.md).
// In the image plane the difference is seen in the registration picture (the fit leaves ~3 px RMS);
// in depth it is not, but the landmark lies on the face's surface: at registration the ray through
// each detected landmark of the frontal picture is followed to where it meets the fitted CANDIDE-3
// mesh, and that point (the picture's position, the mesh's depth there) is the person's landmark.
// Kept as an offset from the mapped point. Why the mesh's depth and not the mapped point's: the
// mapped point's depth is off by several mm on a real head's relief, which reads as a pitch bias
// (docs/face.md gives the registered depths' error with each).
#include <Eigen/Geometry>

#include "core/candide3.hpp"
#include "localization/face/face_landmark_model.hpp"
#include "localization/face/pnp_solvers.hpp"

namespace labo::face {

// 3 x n offsets (metres, face frame) from model.points_m(tau, ipd_m) to where the rays through
// `ideal_pixels` (2 x n, the model's landmarks in the registration picture, camera at `T_cam_face`)
// first meet the fitted CANDIDE-3 mesh. A landmark whose ray misses the mesh, or whose hit lies farther
// than `max_offset_m` from its mapped point in the face's plane (x, y; the depth is the mesh's),
// keeps a zero offset. The moved points are then scaled
// about the face origin so that the eye centres keep the mapped points' distance (the interpupillary
// distance stays the metric scale).
Eigen::Matrix3Xd surface_landmark_offsets(const Candide3Model& candide, const FaceLandmarkModel& model,
                                          const Eigen::VectorXd& tau, double ipd_m, const Eigen::Isometry3d& T_cam_face,
                                          const Eigen::Matrix2Xd& ideal_pixels, const IdealPinhole& camera,
                                          double max_offset_m);

}  // namespace labo::face
