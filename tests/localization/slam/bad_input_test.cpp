#include <catch2/catch.hpp>

#include "slam_test_helpers.hpp"

using namespace labo;
using namespace labo::slam;
using namespace labo::bench;  // the synthetic room and its flights

TEST_CASE("slam: invalid intrinsics and settings are refused at construction") {
  CameraIntrinsics k = PinholeCamera::ardrone2_front().intrinsics();
  const PinholeCamera good(k);
  SlamSettings s;
  s.pyramid_levels = 3;
  CHECK_THROWS_WITH(SlamSystem(good, s), Catch::Contains("pyramid_levels"));
  s = {};
  s.quality_lost = 0.5;
  CHECK_THROWS_WITH(SlamSystem(good, s), Catch::Contains("quality"));
  k.fx = -1;
  CHECK_THROWS_AS(PinholeCamera(k), std::invalid_argument);
  k = good.intrinsics();
  k.cy = std::nan("");
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("finite"));
  k = good.intrinsics();
  k.cx = 700;
  CHECK_THROWS_WITH(PinholeCamera(k), Catch::Contains("principal point"));
  // Valid numbers, but a lens that folds over inside the image (no inverse): the SLAM refuses it.
  k = good.intrinsics();
  k.k1 = -3.0;
  k.k2 = 0.0;
  CHECK_THROWS_WITH(SlamSystem(PinholeCamera(k), testing::synchronous()), Catch::Contains("cannot be inverted"));
  // The AR.Drone's strong lens (k1 = -0.53) is fine.
  CHECK_NOTHROW(SlamSystem(good, testing::synchronous()));
}

TEST_CASE("slam: bad frames and timestamps never corrupt the map") {
  const PinholeCamera camera = PinholeCamera::ardrone2_front();
  const SyntheticRoom room(camera);
  SlamSystem slam(camera, testing::synchronous());
  const Flight flight = approach_flight(room.panel_center());
  const auto frames = testing::first_seconds(flight, 5.0);

  // Before any map: black, saturated and textureless frames keep it initializing.
  const cv::Mat black = cv::Mat::zeros(camera.height(), camera.width(), CV_8U);
  const cv::Mat white(camera.height(), camera.width(), CV_8U, cv::Scalar(255));
  const cv::Mat grey(camera.height(), camera.width(), CV_8U, cv::Scalar(128));
  Seconds t = -1.0;
  for (const cv::Mat* m : {&black, &white, &grey}) {
    t += 0.1;
    const SlamResult r = slam.track(*m, t);
    CHECK(r.state == TrackingState::Initializing);
    CHECK_FALSE(r.T_cam_map);
  }
  const auto run = testing::run(slam, room, frames);
  REQUIRE(run.results.back().T_cam_map);
  const SlamStatus before = slam.status();
  const Seconds last_t = frames.back().t;

  SECTION("duplicate and decreasing timestamps are refused, the map untouched") {
    const cv::Mat image = room.render(frames.back().T_world_cam, 77);
    SlamResult r = slam.track(image, last_t);
    CHECK(r.state == TrackingState::Lost);
    CHECK(r.reason.find("not after") != std::string::npos);
    r = slam.track(image, last_t - 1.0);
    CHECK(r.reason.find("not after") != std::string::npos);
    r = slam.track(image, std::nan(""));
    CHECK(r.reason.find("finite") != std::string::npos);
    CHECK(slam.status().keyframes == before.keyframes);
    CHECK(slam.status().map_points == before.map_points);
    // The next valid frame tracks as if nothing happened.
    CHECK(slam.track(image, last_t + 1.0 / 30).T_cam_map);
  }

  SECTION("frames of the wrong size or type are refused") {
    const cv::Mat small(100, 100, CV_8U, cv::Scalar(0));
    CHECK(slam.track(small, last_t + 0.1).reason.find("100x100") != std::string::npos);
    const cv::Mat colour(camera.height(), camera.width(), CV_8UC3, cv::Scalar(0, 0, 0));
    CHECK(slam.track(colour, last_t + 0.2).reason.find("8-bit grey") != std::string::npos);
    CHECK(slam.track(cv::Mat(), last_t + 0.3).reason.find("empty") != std::string::npos);
  }

  SECTION("black, saturated and textureless frames lose tracking without touching the map") {
    Seconds tt = last_t;
    for (int i = 0; i < 10; ++i) {
      for (const cv::Mat* m : {&black, &white, &grey}) {
        tt += 1.0 / 30;
        const SlamResult r = slam.track(*m, tt);
        CHECK_FALSE(r.T_cam_map);
        CHECK_FALSE(r.keyframe_added);
      }
    }
    CHECK(slam.status().state == TrackingState::Lost);
    CHECK(slam.status().keyframes == before.keyframes);
    CHECK(slam.status().map_points == before.map_points);
    // Random noise: no structure to match either.
    cv::Mat noise(camera.height(), camera.width(), CV_8U);
    cv::randu(noise, 0, 255);
    tt += 1.0 / 30;
    CHECK_FALSE(slam.track(noise, tt).keyframe_added);
    CHECK(slam.status().keyframes == before.keyframes);
  }

  SECTION("reset starts over") {
    slam.reset();
    CHECK(slam.status().keyframes == 0);
    CHECK(slam.status().state == TrackingState::Initializing);
  }
}
