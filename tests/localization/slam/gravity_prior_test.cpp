// The gravity prior (docs/slam.md): the IMU's roll and pitch given with a frame hold the tilt of the
// tracker's pose and of the keyframes in the adjustments. In front of one wall a pitch and a vertical
// translation move the image alike; the prior decides between them.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "core/frames.hpp"
#include "localization/slam/optimize/bundle_adjuster.hpp"
#include "localization/slam/optimize/pose_optimizer.hpp"
#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;
using namespace labo::bench;  // the synthetic room and its flights

namespace {

constexpr double kDeg = M_PI / 180.0;
const Eigen::Vector3d kDownWorld(0, 0, -1);

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.normalized().cross(b.normalized()).norm(), a.normalized().dot(b.normalized())) / kDeg;
}

// Points on the wall x = 8 m in front of a camera at `T_world_cam`, spread over the image, and their
// exact ideal pixels. The map is the world frame here.
std::vector<PoseObservation> wall_observations(const IdealCamera& camera, const Eigen::Isometry3d& T_world_cam) {
  std::vector<PoseObservation> out;
  for (double y = 1.0; y <= 5.0; y += 0.25) {
    for (double z = 0.6; z <= 2.0; z += 0.2) {
      const Eigen::Vector3d p(8.0, y, z);
      const auto px = camera.project(T_world_cam.inverse() * p);
      if (px && px->x() > 0 && px->x() < 640 && px->y() > 0 && px->y() < 360) out.push_back({p, *px, 1.0, true});
    }
  }
  return out;
}

}  // namespace

TEST_CASE("slam gravity: the real and ideal directions agree with the flights' conventions") {
  // Level body: the front camera's "down" is its +y axis; nose down 10 deg: down tilts towards +z
  // (the optical axis looks below the horizon).
  const Eigen::Isometry3d T_body_cam = T_body_cam_front();
  CHECK(angle_deg(gravity_down_in_camera(0, 0, T_body_cam), Eigen::Vector3d::UnitY()) < 1e-9);
  for (const double pitch : {-0.2, 0.1, 0.3}) {
    for (const double roll : {-0.15, 0.0, 0.05}) {
      const Eigen::Isometry3d T_world_cam = make_pose({1, 2, 1}, 0.7, pitch, roll) * T_body_cam;
      const Eigen::Vector3d truth = T_world_cam.linear().transpose() * kDownWorld;
      CHECK(angle_deg(gravity_down_in_camera(roll, pitch, T_body_cam), truth) < 1e-9);
    }
  }
}

TEST_CASE("slam gravity: the pose update follows the images or the IMU by their weights") {
  const IdealCamera camera(PinholeCamera::ardrone2_front());
  const Eigen::Isometry3d T_world_cam = make_pose({5.5, 3.0, 1.3}, 0.1, 0.02, -0.01) * T_body_cam_front();
  const Eigen::Isometry3d truth = T_world_cam.inverse();  // T_cam_map, map = world
  std::vector<PoseObservation> obs = wall_observations(camera, T_world_cam);
  REQUIRE(obs.size() > 40);
  const Eigen::Vector3d true_down_cam = truth.linear() * kDownWorld;
  const auto start = [&] {
    Eigen::Isometry3d T = truth;
    T = Eigen::AngleAxisd(0.8 * kDeg, Eigen::Vector3d(1, 0.3, 0).normalized()) * T;
    T.translation() += Eigen::Vector3d(0.02, -0.03, 0.01);
    return T;
  };
  SECTION("an IMU that agrees with the images changes nothing") {
    Eigen::Isometry3d T = start();
    const int inliers = optimize_pose(camera, obs, T, {}, GravityPrior{kDownWorld, true_down_cam, 0.1 * kDeg});
    CHECK(inliers == static_cast<int>(obs.size()));
    CHECK(Eigen::AngleAxisd(T.linear() * truth.linear().transpose()).angle() / kDeg < 1e-4);
    CHECK((T.translation() - truth.translation()).norm() < 1e-5);
  }
  // The IMU says the camera is pitched 1 deg further than the images do.
  const Eigen::Vector3d tilted_down_cam = Eigen::AngleAxisd(1.0 * kDeg, Eigen::Vector3d::UnitX()) * true_down_cam;
  SECTION("a precise IMU sets the tilt, the images the rest") {
    Eigen::Isometry3d T = start();
    optimize_pose(camera, obs, T, {}, GravityPrior{kDownWorld, tilted_down_cam, 0.001 * kDeg});
    CHECK(angle_deg(T.linear() * kDownWorld, tilted_down_cam) < 0.01);
    // The heading about gravity is the images' alone.
    const Eigen::Vector3d forward_truth = truth.linear().transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d forward = T.linear().transpose() * Eigen::Vector3d::UnitZ();
    CHECK(std::abs(std::atan2(forward.y(), forward.x()) - std::atan2(forward_truth.y(), forward_truth.x())) / kDeg < 0.05);
  }
  SECTION("a vague IMU leaves the images in charge") {
    Eigen::Isometry3d T = start();
    optimize_pose(camera, obs, T, {}, GravityPrior{kDownWorld, tilted_down_cam, 10.0 * kDeg});
    CHECK(Eigen::AngleAxisd(T.linear() * truth.linear().transpose()).angle() / kDeg < 0.02);
  }
}

TEST_CASE("slam gravity: a global adjustment estimates the map's gravity direction, a local one holds it") {
  const IdealCamera camera(PinholeCamera::ardrone2_front());
  // The map's frame is tilted against the world (as the first keyframe's camera frame is).
  Eigen::Isometry3d T_world_map = Eigen::Isometry3d::Identity();
  T_world_map.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Eigen::Vector3d true_down_map = T_world_map.linear().transpose() * kDownWorld;
  BundleProblem problem;
  const double yaws[] = {0.0, 0.15, 0.3, 0.45};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Isometry3d T_world_cam = make_pose({5.0, 3.0 - 0.2 * k, 1.3}, yaws[k], 0.03 * k, -0.02 * k) * T_body_cam_front();
    const Eigen::Isometry3d T_cam_map = T_world_cam.inverse() * T_world_map;
    problem.poses[k] = T_cam_map;
    problem.pose_fixed[k] = k == 0;
    problem.down_cam[k] = T_world_cam.linear().transpose() * kDownWorld;
    for (const PoseObservation& o : wall_observations(camera, T_world_cam)) {
      const PointId id = static_cast<PointId>(std::lround(o.p_map.y() * 100) * 1000 + std::lround(o.p_map.z() * 100));
      problem.points[id] = T_world_map.inverse() * o.p_map;
      problem.observations.push_back({k, id, o.px, 1.0});
    }
  }
  problem.gravity_sigma_rad = 0.2 * kDeg;
  const Eigen::Vector3d off = Eigen::AngleAxisd(3.0 * kDeg, Eigen::Vector3d(1, 1, 0).normalized()) * true_down_map;
  SECTION("global: estimated") {
    problem.down_map = off;
    problem.down_map_fixed = false;
    solve_bundle(camera, problem, BundleSettings{}, nullptr);
    REQUIRE(problem.down_map);
    CHECK(angle_deg(*problem.down_map, true_down_map) < 0.01);
  }
  SECTION("local: held") {
    problem.down_map = off;
    problem.down_map_fixed = true;
    solve_bundle(camera, problem, BundleSettings{}, nullptr);
    REQUIRE(problem.down_map);
    CHECK(angle_deg(*problem.down_map, off) < 1e-9);
  }
}

TEST_CASE("slam gravity: the system keeps the map's gravity direction from the frames' attitudes") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSettings settings = testing::synchronous();
  settings.gravity_sigma_deg = 0.3;
  SlamSystem with(camera, settings);
  SlamSystem without(camera, testing::synchronous());
  const auto frames = testing::first_seconds(tour_flight(), 8.0);
  int used = 0, tracked = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat image = room.render(frames[i].T_world_cam, static_cast<unsigned>(i));
    const GravityMeasurement imu{frames[i].t, frames[i].T_world_cam.linear().transpose() * kDownWorld};
    const SlamResult r = with.track(image, frames[i].t, std::nullopt, imu);
    without.track(image, frames[i].t, std::nullopt, imu);
    tracked += r.T_cam_map ? 1 : 0;
    used += r.gravity_used ? 1 : 0;
  }
  INFO(tracked << " frames tracked, " << used << " with the gravity prior");
  CHECK(tracked > static_cast<int>(frames.size()) / 2);
  CHECK(used > tracked - 5);  // every frame tracked against the map (not the initialization's)
  const SlamStatus status = with.status();
  REQUIRE(status.down_map);
  REQUIRE(status.keyframes > 3);
  CHECK_FALSE(without.status().down_map);  // without a sigma the attitudes are ignored
  // Every keyframe's camera should see gravity where the map says it is (the truth's, not the
  // IMU's). Without the prior the map's own best guess, the keyframes' mean, is the reference.
  const auto tilt_errors_deg = [&](const SlamStatus& s, std::optional<Eigen::Vector3d> down_map) {
    std::vector<Eigen::Vector3d> seen;
    for (std::size_t k = 0; k < s.keyframes_T_map_cam.size(); ++k) {
      const auto truth = std::find_if(frames.begin(), frames.end(), [&](const FlightFrame& f) { return f.t == s.keyframe_times[k]; });
      REQUIRE(truth != frames.end());
      seen.push_back(s.keyframes_T_map_cam[k].linear() * (truth->T_world_cam.linear().transpose() * kDownWorld));
    }
    if (!down_map) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& d : seen) mean += d;
      down_map = mean.normalized();
    }
    double worst = 0, sum = 0;
    for (const auto& d : seen) {
      worst = std::max(worst, angle_deg(d, *down_map));
      sum += angle_deg(d, *down_map);
    }
    return std::pair{worst, sum / static_cast<double>(seen.size())};
  };
  const auto [with_worst, with_mean] = tilt_errors_deg(status, status.down_map);
  const auto [without_worst, without_mean] = tilt_errors_deg(without.status(), std::nullopt);
  INFO("keyframes' tilt against the map's gravity: with the prior worst " << with_worst << " deg, mean " << with_mean
       << "; without worst " << without_worst << " deg, mean " << without_mean);
  CHECK(with_worst < 0.5);
  CHECK(with_mean < 0.75 * without_mean);

  // A saved map keeps its gravity direction: a system that loads it starts from the same "down".
  with.wait_for_mapping();
  const Eigen::Vector3d saved_down = *with.status().down_map;
  const auto file = std::filesystem::temp_directory_path() / ("labodrone_gravity_map_" + std::to_string(::getpid()) + ".bin");
  with.save_map(file);
  SlamSystem loaded(camera, settings);
  loaded.load_map(file);
  std::filesystem::remove(file);
  REQUIRE(loaded.status().down_map);
  CHECK(angle_deg(*loaded.status().down_map, saved_down) < 1e-9);
}

TEST_CASE("slam gravity: a malformed attitude refuses the frame") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSettings settings = testing::synchronous();
  settings.gravity_sigma_deg = 0.5;
  SlamSystem slam(camera, settings);
  const cv::Mat image = room.render(tour_flight().frames.front().T_world_cam, 0);
  const SlamResult nan = slam.track(image, 1.0, std::nullopt, GravityMeasurement{1.0, Eigen::Vector3d(std::nan(""), 1, 0)});
  CHECK(nan.state == TrackingState::Lost);
  CHECK_THAT(nan.reason, Catch::Contains("gravity direction"));
  const SlamResult zero = slam.track(image, 1.0, std::nullopt, GravityMeasurement{1.0, Eigen::Vector3d::Zero()});
  CHECK_THAT(zero.reason, Catch::Contains("gravity direction"));
  const SlamResult late = slam.track(image, 1.0, std::nullopt, GravityMeasurement{0.9, Eigen::Vector3d::UnitY()});
  CHECK_THAT(late.reason, Catch::Contains("attitude stamped"));
  // Refused frames change nothing: the same timestamp is still accepted.
  const SlamResult ok = slam.track(image, 1.0, std::nullopt, GravityMeasurement{1.0, Eigen::Vector3d::UnitY()});
  CHECK(ok.state == TrackingState::Initializing);
  CHECK(ok.reason.find("refused") == std::string::npos);
}
