#pragma once
// Similarity transforms for loop closure. A monocular map drifts in scale as well as in pose, so the
// correction that brings a drifted part of the map back onto its older part is a Sim(3):
// y = scale * R * x + t. Keyframe poses (rigid T_cam_map) are Sim(3)s with scale 1; after a
// correction a keyframe's similarity is turned back into a rigid pose of the corrected map by
// dividing its translation by its scale (the camera sees the same image, the world is rescaled).
#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace labo::slam {

struct Similarity3 {
  double scale = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  static Similarity3 from_rigid(const Eigen::Isometry3d& T) { return {1.0, T.linear(), T.translation()}; }

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const { return scale * (R * x) + t; }
  Similarity3 operator*(const Similarity3& o) const { return {scale * o.scale, R * o.R, scale * (R * o.t) + t}; }
  Similarity3 inverse() const {
    const Eigen::Matrix3d Rt = R.transpose();
    return {1.0 / scale, Rt, -(Rt * t) / scale};
  }
  // The rigid camera pose that sees through this similarity: x_cam = (s R x + t) / s.
  Eigen::Isometry3d rigid_pose() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t / scale;
    return T;
  }
};

// Seven optimisation parameters of a similarity: angle-axis (3), translation (3), log scale (1).
using Sim3Parameters = std::array<double, 7>;

inline Sim3Parameters to_parameters(const Similarity3& S) {
  const Eigen::AngleAxisd aa(S.R);
  const Eigen::Vector3d r = aa.angle() * aa.axis();
  return {r.x(), r.y(), r.z(), S.t.x(), S.t.y(), S.t.z(), std::log(S.scale)};
}

inline Similarity3 from_parameters(const Sim3Parameters& x) {
  Similarity3 S;
  const Eigen::Vector3d r(x[0], x[1], x[2]);
  if (r.norm() > 1e-15) S.R = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  S.t = Eigen::Vector3d(x[3], x[4], x[5]);
  S.scale = std::exp(x[6]);
  return S;
}

}  // namespace labo::slam
