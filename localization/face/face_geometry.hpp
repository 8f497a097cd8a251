#pragma once
// Head angles of a face pose, as the paper's Table 1 reports them. R_cam_face = Q · F where
// F = diag(1, -1, -1) is the face looking straight into the camera (CANDIDE +y up, +z out of the face
// against OpenCV's y down, z forward) and Q = Ry(yaw) · Rx(pitch) · Rz(roll) is the head's rotation
// about the camera's axes: yaw turns the head about the vertical, pitch nods, roll tilts.
#include <Eigen/Geometry>

namespace labo::face {

struct HeadAngles {
  double yaw = 0, pitch = 0, roll = 0;  // radians
};

Eigen::Matrix3d head_rotation(const HeadAngles& angles);  // R_cam_face
HeadAngles head_angles(const Eigen::Matrix3d& R_cam_face);
// The direction the face looks (its +z axis) in camera coordinates; (0, 0, -1) when it faces the camera.
inline Eigen::Vector3d line_of_sight(const Eigen::Matrix3d& R_cam_face) { return R_cam_face.col(2); }

}  // namespace labo::face
