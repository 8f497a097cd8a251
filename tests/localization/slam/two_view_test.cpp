#include <catch2/catch.hpp>
#include <random>

#include "core/camera_model.hpp"
#include "localization/slam/camera/ideal_camera.hpp"
#include "localization/slam/initialize/two_view_geometry.hpp"
#include "localization/slam/optimize/se3.hpp"
#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;
using namespace labo::bench;  // the synthetic room and its flights

namespace {

struct Pair {
  std::vector<Eigen::Vector2d> a, b;
};

// Points seen by two cameras, projected in ideal pixels with 0.5 px noise.
Pair project_pair(const IdealCamera& cam, const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& T21) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  Pair p;
  for (const auto& X : points) {
    const auto a = cam.project(X), b = cam.project(T21 * X);
    if (!a || !b) continue;
    p.a.push_back(*a + Eigen::Vector2d(noise(rng), noise(rng)));
    p.b.push_back(*b + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  return p;
}

Eigen::Isometry3d second_camera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-0.3, 0.05, 0.02);
  return T;
}

}  // namespace

TEST_CASE("slam: two-view reconstruction picks the essential matrix for a 3-D scene and recovers the motion") {
  const IdealCamera cam(PinholeCamera::ardrone2_front());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> x(-2, 2), y(-1, 1), z(2, 6);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) points.emplace_back(x(rng), y(rng), z(rng));
  const Eigen::Isometry3d T21 = second_camera();
  const Pair p = project_pair(cam, points, T21);
  const TwoViewOutcome out = reconstruct_two_views(cam, p.a, p.b, {});
  REQUIRE(out.reconstruction);
  CHECK(out.reconstruction->model == TwoViewModel::Essential);
  // Within ~1 degree from the RANSAC essential matrix alone (bundle adjustment refines it later).
  CHECK(rotation_angle(out.reconstruction->T_second_first.inverse() * T21) < 0.02);
  const double cos_t = out.reconstruction->T_second_first.translation().normalized().dot(T21.translation().normalized());
  CHECK(cos_t > 0.995);
  CHECK(out.reconstruction->points.size() > 250);
}

TEST_CASE("slam: two-view reconstruction picks the homography for a planar scene") {
  const IdealCamera cam(PinholeCamera::ardrone2_front());
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> x(-2, 2), y(-1, 1);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) points.emplace_back(x(rng), y(rng), 3.0 + 0.2 * x(rng) * 0);
  const Eigen::Isometry3d T21 = second_camera();
  const Pair p = project_pair(cam, points, T21);
  const TwoViewOutcome out = reconstruct_two_views(cam, p.a, p.b, {});
  REQUIRE(out.reconstruction);
  CHECK(out.reconstruction->model == TwoViewModel::Homography);
  CHECK(out.reconstruction->homography_share > 0.45);
  CHECK(rotation_angle(out.reconstruction->T_second_first.inverse() * T21) < 0.02);
  const double cos_t = out.reconstruction->T_second_first.translation().normalized().dot(T21.translation().normalized());
  CHECK(cos_t > 0.98);
}

TEST_CASE("slam: two-view reconstruction refuses too little parallax") {
  const IdealCamera cam(PinholeCamera::ardrone2_front());
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> x(-2, 2), y(-1, 1), z(2, 6);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) points.emplace_back(x(rng), y(rng), z(rng));
  Eigen::Isometry3d T21 = Eigen::Isometry3d::Identity();
  T21.translation() = Eigen::Vector3d(0.005, 0, 0);
  const Pair p = project_pair(cam, points, T21);
  const TwoViewOutcome out = reconstruct_two_views(cam, p.a, p.b, {});
  CHECK_FALSE(out.reconstruction);
  CHECK_FALSE(out.reason.empty());
}

TEST_CASE("slam: initializes automatically from the take-off climb in the synthetic room") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSystem slam(camera, testing::synchronous());
  const Flight flight = approach_flight(room.panel_center());
  const auto run = testing::run(slam, room, testing::first_seconds(flight, 3.5));
  REQUIRE(run.tracked.size() > 20);
  CHECK(run.results.front().state == TrackingState::Initializing);
  // The first estimated motion points the way the drone climbed (up = -y in the camera).
  const PosePair& first = run.tracked.front();
  const PosePair& last = run.tracked.back();
  const Eigen::Vector3d est = (last.estimate_T_map_cam.translation() - first.estimate_T_map_cam.translation()).normalized();
  const Eigen::Vector3d truth_cam =
      first.truth_T_world_cam.linear().transpose() * (last.truth_T_world_cam.translation() - first.truth_T_world_cam.translation());
  const Eigen::Vector3d est_cam = first.estimate_T_map_cam.linear().transpose() * est;
  CHECK(est_cam.dot(truth_cam.normalized()) > 0.95);
  const SlamStatus status = slam.status();
  CHECK(status.keyframes >= 2);
  CHECK(status.map_points >= 60);
}
