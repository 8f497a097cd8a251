#pragma once
// Small SE(3) helpers: the exponential map for pose updates (E' = exp(mu) * E, as PTAM writes it)
// and the fractional motion used by the decaying-velocity motion model.
#include <Eigen/Geometry>

namespace labo::slam {

// exp of a twist (v, w): translation part first, rotation part second.
inline Eigen::Isometry3d se3_exp(const Eigen::Matrix<double, 6, 1>& xi) {
  const Eigen::Vector3d v = xi.head<3>(), w = xi.tail<3>();
  const double theta = w.norm();
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  Eigen::Matrix3d R, V;
  if (theta < 1e-9) {
    R = Eigen::Matrix3d::Identity() + W;
    V = Eigen::Matrix3d::Identity() + 0.5 * W;
  } else {
    const double a = std::sin(theta) / theta, b = (1 - std::cos(theta)) / (theta * theta),
                 c = (theta - std::sin(theta)) / (theta * theta * theta);
    R = Eigen::Matrix3d::Identity() + a * W + b * W * W;
    V = Eigen::Matrix3d::Identity() + b * W + c * W * W;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = V * v;
  return T;
}

// The motion `delta` scaled by `fraction` (rotation angle and translation scaled alike).
inline Eigen::Isometry3d scale_motion(const Eigen::Isometry3d& delta, double fraction) {
  Eigen::AngleAxisd aa(delta.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::AngleAxisd(aa.angle() * fraction, aa.axis()).toRotationMatrix();
  out.translation() = delta.translation() * fraction;
  return out;
}

// Rotation angle of a transform, radians.
inline double rotation_angle(const Eigen::Isometry3d& T) { return Eigen::AngleAxisd(T.linear()).angle(); }

}  // namespace labo::slam
