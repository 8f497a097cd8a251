#include "localization/planar/pose/ippe.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>

namespace labo::planar {

namespace {

// The projective basis of four points (homogeneous): the 3x3 map taking e1, e2, e3 and (1, 1, 1)
// to them. Empty when three of them are collinear.
std::optional<Eigen::Matrix3d> projective_basis(const std::array<Eigen::Vector3d, 4>& p) {
  Eigen::Matrix3d M;
  M << p[0], p[1], p[2];
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(M);
  if (!lu.isInvertible()) return std::nullopt;
  const Eigen::Vector3d scale = lu.solve(p[3]);
  const double largest = scale.cwiseAbs().maxCoeff();
  if (!(largest > 0) || !(scale.cwiseAbs().minCoeff() > 1e-12 * largest)) return std::nullopt;
  return Eigen::Matrix3d(M * scale.asDiagonal());
}

// The top-left 2x2 block of a rotation completed into the rotation; `sign` picks which of the two
// completions (the third column's first two entries are known up to a common sign).
Eigen::Matrix3d complete_rotation(const Eigen::Matrix2d& block, double sign) {
  const double b1 = std::sqrt(std::max(0.0, 1.0 - block.row(0).squaredNorm()));
  double b2 = std::sqrt(std::max(0.0, 1.0 - block.row(1).squaredNorm()));
  // The first two rows are orthogonal: r11 r21 + r12 r22 + r13 r23 = 0 fixes the relative sign.
  if (block.row(0).dot(block.row(1)) > 0) b2 = -b2;
  Eigen::Matrix3d R;
  R.row(0) << block(0, 0), block(0, 1), sign * b1;
  R.row(1) << block(1, 0), block(1, 1), sign * b2;
  R.row(2) = R.row(0).cross(R.row(1));
  return R;
}

}  // namespace

std::optional<std::array<IppeSolution, 2>> ippe_four_points(const std::array<Eigen::Vector2d, 4>& object_xy,
                                                            const std::array<Eigen::Vector2d, 4>& image_px,
                                                            const IppeIntrinsics& k) {
  // Normalized image coordinates, and the object points centred on their centroid: the Jacobian is
  // taken there.
  std::array<Eigen::Vector2d, 4> q;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < 4; ++i) {
    q[i] = Eigen::Vector2d((image_px[i].x() - k.cx) / k.fx, (image_px[i].y() - k.cy) / k.fy);
    centroid += 0.25 * object_xy[i];
  }
  std::array<Eigen::Vector3d, 4> plane_h, image_h;
  for (std::size_t i = 0; i < 4; ++i) {
    plane_h[i] = (object_xy[i] - centroid).homogeneous();
    image_h[i] = q[i].homogeneous();
  }
  const auto plane_basis = projective_basis(plane_h);
  const auto image_basis = projective_basis(image_h);
  if (!plane_basis || !image_basis) return std::nullopt;
  Eigen::Matrix3d H = *image_basis * plane_basis->inverse();
  if (!(std::abs(H(2, 2)) > 1e-12 * H.cwiseAbs().maxCoeff())) return std::nullopt;  // centroid at infinity
  H /= H(2, 2);

  // v: the centroid's image; J: the Jacobian of the plane -> image map there.
  const Eigen::Vector2d v(H(0, 2), H(1, 2));
  Eigen::Matrix2d J;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) J(i, j) = H(i, j) - v(i) * H(2, j);
  }
  // R_v: the smallest rotation taking the optical axis onto the ray through v (about the axis
  // e_z x ray, by the angle between them).
  Eigen::Matrix3d Rv = Eigen::Matrix3d::Identity();
  const double v_norm = v.norm();
  if (v_norm > 0) {
    const double n = std::sqrt(1.0 + v_norm * v_norm);
    const double c = 1.0 / n, s = v_norm / n;
    const double kx = -v.y() / v_norm, ky = v.x() / v_norm;
    Rv << c + kx * kx * (1 - c), kx * ky * (1 - c), ky * s,  //
        kx * ky * (1 - c), c + ky * ky * (1 - c), -kx * s,   //
        -ky * s, kx * s, c;
  }
  Eigen::Matrix2d B;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) B(i, j) = Rv(i, j) - v(i) * Rv(2, j);
  }
  if (!(std::abs(B.determinant()) > 1e-12)) return std::nullopt;
  const Eigen::Matrix2d A = B.inverse() * J;
  // The largest singular value of A, in closed form for 2x2: A = [[a, b], [c, d]] is the sum of a
  // scaled rotation and a scaled reflection, sigma_max = |((a+d)/2, (c-b)/2)| + |((a-d)/2, (c+b)/2)|.
  // (Not sqrt((S + sqrt(S^2 - 4 det^2)) / 2): near fronto-parallel A is nearly a scaled rotation, and
  // S^2 - 4 det^2 cancels, which cost 1e-8 in the rotation at 0.3 deg of tilt.)
  const double gamma = std::hypot(0.5 * (A(0, 0) + A(1, 1)), 0.5 * (A(1, 0) - A(0, 1))) +
                       std::hypot(0.5 * (A(0, 0) - A(1, 1)), 0.5 * (A(1, 0) + A(0, 1)));
  if (!(gamma > 0)) return std::nullopt;
  const Eigen::Matrix2d block = A / gamma;

  std::array<IppeSolution, 2> out;
  for (std::size_t s = 0; s < 2; ++s) {
    IppeSolution& sol = out[s];
    sol.R = Rv * complete_rotation(block, s == 0 ? 1.0 : -1.0);
    // t by linear least squares: R X + t along the point's ray, [1 0 -x; 0 1 -y] (R X + t) = 0.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 4; ++i) {
      const Eigen::Vector3d r = sol.R.leftCols<2>() * object_xy[i];
      const Eigen::Vector3d row_x(1, 0, -q[i].x()), row_y(0, 1, -q[i].y());
      normal += row_x * row_x.transpose() + row_y * row_y.transpose();
      rhs += row_x * (q[i].x() * r.z() - r.x()) + row_y * (q[i].y() * r.z() - r.y());
    }
    sol.t = normal.ldlt().solve(rhs);
    double squared = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const Eigen::Vector3d p = sol.R.leftCols<2>() * object_xy[i] + sol.t;
      const Eigen::Vector2d projected(k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy);
      squared += (projected - image_px[i]).squaredNorm();
    }
    sol.rms_px = std::sqrt(squared / 8.0);
    if (!sol.R.allFinite() || !sol.t.allFinite() || !std::isfinite(sol.rms_px)) return std::nullopt;
  }
  if (out[1].rms_px < out[0].rms_px) std::swap(out[0], out[1]);
  return out;
}

}  // namespace labo::planar
