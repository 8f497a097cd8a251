#pragma once
// Rigid transforms between named frames, with the `T_a_b` convention: T_a_b maps coordinates in
// frame b to frame a, so T_a_c = T_a_b * T_b_c. FramedTransform carries the two frame names and
// refuses to compose transforms whose frames do not chain: a wrong cascade fails loudly instead of
// producing a plausible, wrong pose.
//
// Conventions (docs/architecture.md): world is the lab, z up, origin at the base; body is the drone,
// x forward, y left, z up; cameras are OpenCV-style, x right, y down, z along the optical axis.
// Angles are radians, yaw counter-clockwise about z (the AR.Drone's clockwise psi is converted at the
// driver's edge).
#include <Eigen/Geometry>
#include <string>

namespace labo {

enum class FrameKind { World, Body, CamFront, CamBottom, Map, Object, Face };

struct FrameId {
  FrameKind kind = FrameKind::World;
  int index = 0;  // which object (object:<index>); 0 for the others

  static FrameId world() { return {FrameKind::World, 0}; }
  static FrameId body() { return {FrameKind::Body, 0}; }
  static FrameId cam_front() { return {FrameKind::CamFront, 0}; }
  static FrameId cam_bottom() { return {FrameKind::CamBottom, 0}; }
  static FrameId map() { return {FrameKind::Map, 0}; }
  static FrameId object(int index) { return {FrameKind::Object, index}; }
  static FrameId face() { return {FrameKind::Face, 0}; }

  friend bool operator==(const FrameId&, const FrameId&) = default;
};

std::string to_string(FrameId frame);

class FramedTransform {
 public:
  FramedTransform(FrameId to, FrameId from, const Eigen::Isometry3d& T_to_from)
      : to_(to), from_(from), T_(T_to_from) {}

  static FramedTransform identity(FrameId to, FrameId from) {
    return {to, from, Eigen::Isometry3d::Identity()};
  }

  FrameId to() const { return to_; }
  FrameId from() const { return from_; }
  const Eigen::Isometry3d& T() const { return T_; }

  // T_a_b * T_b_c = T_a_c; throws std::logic_error naming the frames when b does not match.
  FramedTransform operator*(const FramedTransform& rhs) const;
  FramedTransform inverse() const { return {from_, to_, T_.inverse()}; }
  // A point in frame `from` expressed in frame `to`.
  Eigen::Vector3d apply(const Eigen::Vector3d& p_from) const { return T_ * p_from; }

 private:
  FrameId to_;
  FrameId from_;
  Eigen::Isometry3d T_;
};

// Yaw-pitch-roll (Z-Y-X, intrinsic) rotations, radians.
Eigen::Matrix3d rotation_from_ypr(double yaw, double pitch, double roll);
// Returns (yaw, pitch, roll) with pitch in [-pi/2, pi/2].
Eigen::Vector3d ypr_from_rotation(const Eigen::Matrix3d& R);
// Wraps an angle to [-pi, pi).
double wrap_angle(double rad);
// A pose from x, y, z and yaw-pitch-roll.
Eigen::Isometry3d make_pose(const Eigen::Vector3d& t, double yaw, double pitch = 0.0, double roll = 0.0);

// Camera mountings on the AR.Drone 2.0 body. The front camera looks along body x; the bottom camera
// looks down with the image's top towards the drone's front. `offset_body` is the optical centre in
// the body frame.
Eigen::Isometry3d T_body_cam_front(const Eigen::Vector3d& offset_body = Eigen::Vector3d(0.2, 0.0, 0.0));
Eigen::Isometry3d T_body_cam_bottom(const Eigen::Vector3d& offset_body = Eigen::Vector3d(0.0, 0.0, -0.05));

}  // namespace labo
