#include <catch2/catch.hpp>

#include "localization/planar/pose/planar_pose.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;
using namespace labo::planar;

namespace {

std::array<cv::Point3d, 4> square(double s) {
  return {cv::Point3d(-s / 2, -s / 2, 0), cv::Point3d(s / 2, -s / 2, 0), cv::Point3d(s / 2, s / 2, 0),
          cv::Point3d(-s / 2, s / 2, 0)};
}

std::array<cv::Point2d, 4> project(const cv::Matx33d& K, const Eigen::Isometry3d& T, const std::array<cv::Point3d, 4>& pts) {
  std::array<cv::Point2d, 4> out;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = T * Eigen::Vector3d(pts[i].x, pts[i].y, pts[i].z);
    out[i] = cv::Point2d(K(0, 0) * p.x() / p.z() + K(0, 2), K(1, 1) * p.y() / p.z() + K(1, 2));
  }
  return out;
}

}  // namespace

TEST_CASE("planar: IPPE pose of exact corners matches the truth") {
  const cv::Matx33d K(570, 0, 320, 0, 570, 180, 0, 0, 1);
  const planar::PlanarPoseSolver solver(K, square(0.4));
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.4, -0.2, -1.2), Eigen::Vector3d::Zero(), 0.1);
  const auto pose = solver.solve(project(K, truth, square(0.4)), std::nullopt);
  REQUIRE(pose);
  CHECK((pose->T_cam_object.translation() - truth.translation()).norm() < 1e-3);
  CHECK(rotation_angle(pose->T_cam_object.linear(), truth.linear()) < 1e-3);
  CHECK(pose->reprojection_error_px < 0.01);
}

TEST_CASE("planar: the IPPE two-fold ambiguity is resolved by continuity") {
  const cv::Matx33d K(570, 0, 320, 0, 570, 180, 0, 0, 1);
  const planar::PlanarPoseSolver solver(K, square(0.2));
  // Far and nearly frontal: both IPPE solutions reproject within noise.
  const Eigen::Isometry3d truth = look_at_object(Eigen::Vector3d(0.25, 0.0, -3.0), Eigen::Vector3d(0, 0, 0));
  auto corners = project(K, truth, square(0.2));
  corners[0] += cv::Point2d(0.2, -0.1);  // a little corner noise
  corners[2] += cv::Point2d(-0.1, 0.2);
  const auto alone = solver.solve(corners, std::nullopt);
  REQUIRE(alone);
  REQUIRE(alone->alternative_angle_rad > 2.0 * 3.14159 / 180);  // two distinct candidates
  CHECK(alone->ambiguous);
  // With the previous pose at the truth, the candidate nearer to it wins.
  const auto with_truth = solver.solve(corners, truth);
  REQUIRE(with_truth);
  CHECK_FALSE(with_truth->ambiguous);
  CHECK(rotation_angle(with_truth->T_cam_object.linear(), truth.linear()) <
        rotation_angle(with_truth->T_alternative.linear(), truth.linear()));
  CHECK(rotation_angle(with_truth->T_cam_object.linear(), truth.linear()) < 0.1);
  // With the previous pose at the other candidate, continuity keeps that one.
  const auto with_other = solver.solve(corners, with_truth->T_alternative);
  REQUIRE(with_other);
  CHECK(rotation_angle(with_other->T_cam_object.linear(), with_truth->T_alternative.linear()) < 1e-9);
}

TEST_CASE("planar: a pose behind the camera or seen from the back is refused") {
  const cv::Matx33d K(570, 0, 320, 0, 570, 180, 0, 0, 1);
  const planar::PlanarPoseSolver solver(K, square(0.4));
  // The panel seen from behind: its corners appear mirrored (clockwise order becomes anticlockwise).
  const Eigen::Isometry3d front = look_at_object(Eigen::Vector3d(0, 0, -1.0), Eigen::Vector3d::Zero());
  auto corners = project(K, front, square(0.4));
  std::swap(corners[0], corners[1]);
  std::swap(corners[2], corners[3]);
  CHECK_FALSE(solver.solve(corners, std::nullopt).has_value());
}
