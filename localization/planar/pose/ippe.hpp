#pragma once
// Infinitesimal Plane-based Pose Estimation (Collins & Bartoli, "Infinitesimal Plane-based Pose
// Estimation", IJCV 2014) for the four corners of a planar object, written from the paper's maths
// with fixed-size Eigen types: nothing is allocated, so the planar localizer can run it per frame
// (it replaces cv::solvePnPGeneric(SOLVEPNP_IPPE), which allocates on every call: test "vision
// front-ends: tracking a panel allocates nothing";
// tests/localization/planar/pose/ippe_test.cpp holds the two to 1e-9 on fronto-parallel and oblique views).
//
// The method: the homography H from the plane (object points centred on their centroid) to the
// normalized image is exact for four points. Its Jacobian J at the centroid, with v the centroid's
// image, fixes the rotation up to a two-fold ambiguity: with R_v the smallest rotation taking the
// optical axis onto the ray through v, and B the first two columns of [I2 | -v] R_v,
// J = (1 / t_z) B R~22, where R~22 is the top-left 2x2 block of R~ = R_v^T R. That block has
// singular values 1 and |r~33|, so R~22 = A / sigma_max(A) with A = B^-1 J; orthonormality leaves
// the rest of R~'s first two rows, (r~13, r~23), known up to a common sign: the two solutions. The
// translation of each then follows by linear least squares over the points (the algebraic error:
// (R X + t) parallel to the point's ray). The solutions come ordered by reprojection error, lower
// first.
#include <array>
#include <optional>

#include <Eigen/Core>

namespace labo::planar {

struct IppeSolution {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // camera from object
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  // Reprojection error in pixels, root mean square over the 2N image coordinates (as
  // cv::solvePnPGeneric reports it): sqrt(sum of squared pixel distances / (2 N)).
  double rms_px = 0;
};

// Pinhole intrinsics without skew or distortion; image points are in pixels of that camera.
struct IppeIntrinsics {
  double fx = 1, fy = 1, cx = 0, cy = 0;
};

// The two IPPE poses of four points of the object's z = 0 plane (object_xy: their x, y) seen at
// image_px. Empty when the points are degenerate (three collinear, a homography at infinity) or a
// result is not finite.
std::optional<std::array<IppeSolution, 2>> ippe_four_points(const std::array<Eigen::Vector2d, 4>& object_xy,
                                                            const std::array<Eigen::Vector2d, 4>& image_px,
                                                            const IppeIntrinsics& intrinsics);

}  // namespace labo::planar
