// AttitudeHistory: the navdata's roll and pitch at a video frame's capture time (SLAM's gravity prior).
#include <catch2/catch.hpp>

#include "localization/fusion/attitude_history.hpp"

using namespace labo;
using namespace labo::fusion;

TEST_CASE("attitude history: interpolates at a frame's time, holds the newest briefly, refuses gaps") {
  fusion::AttitudeHistory h;
  CHECK_FALSE(h.at(1.0));
  // 15 Hz navdata, pitch ramping 0.1 rad/s, roll constant.
  for (int i = 0; i <= 30; ++i) h.add(i / 15.0, {0.02, 0.1 * i / 15.0});
  const auto mid = h.at(1.01);
  REQUIRE(mid);
  CHECK(mid->pitch_rad == Approx(0.101).margin(1e-12));
  CHECK(mid->roll_rad == Approx(0.02));
  // Past the newest sample (2.0 s): held up to 0.1 s, then unknown.
  REQUIRE(h.at(2.05));
  CHECK(h.at(2.05)->pitch_rad == Approx(0.2));
  CHECK_FALSE(h.at(2.2));
  // Older than the ring (64 samples kept; 31 here): before the first sample is unknown.
  CHECK_FALSE(h.at(-0.1));
  // A gap in the navdata: no interpolation across it.
  h.add(3.0, {0.0, 0.0});
  CHECK_FALSE(h.at(2.5));
  // Non-finite samples are ignored; a time going back (a new run) starts again.
  h.add(3.1, {std::nan(""), 0.0});
  CHECK(h.at(3.05)->pitch_rad == Approx(0.0));
  h.add(0.5, {0.1, 0.1});
  CHECK_FALSE(h.at(2.9));
  REQUIRE(h.at(0.55));
  CHECK(h.at(0.55)->roll_rad == Approx(0.1));
}

TEST_CASE("attitude history: keeps the last 64 samples") {
  fusion::AttitudeHistory h;
  for (int i = 0; i < 200; ++i) h.add(i * 0.005, {0.0, i * 0.001});
  CHECK_FALSE(h.at(0.005 * 130));          // dropped
  REQUIRE(h.at(0.005 * 140 + 0.0025));     // kept (samples 136..199)
  CHECK(h.at(0.005 * 140 + 0.0025)->pitch_rad == Approx(0.1405));
}

#include "localization/fusion/lab_pipelines.hpp"
#include "core/frames.hpp"
#include "localization/slam/slam_system.hpp"

namespace {

// Records what LabPipelines hands the SLAM front-end.
class RecordingSlam final : public fusion::SlamFrontEnd {
 public:
  explicit RecordingSlam(std::vector<std::optional<Eigen::Vector3d>>& seen) : seen_(seen) {}
  const fusion::SlamFrame& process(const cv::Mat&, Seconds, const std::optional<Eigen::Isometry3d>&,
                           const std::optional<Eigen::Vector3d>& gravity_down_cam) override {
    seen_.push_back(gravity_down_cam);
    return frame_;
  }
  const fusion::SlamFrame& pause() override { return frame_; }
  int map_id() const override { return 1; }

 private:
  std::vector<std::optional<Eigen::Vector3d>>& seen_;
  fusion::SlamFrame frame_;
};

}  // namespace

TEST_CASE("lab pipelines: each front frame goes to SLAM with the IMU's attitude at its capture time") {
  fusion::LabPipelines pipelines(fusion::LabGeometry{}, estimation::EstimatorConfig{}, VisionThresholds{});
  std::vector<std::optional<Eigen::Vector3d>> seen;
  pipelines.set_slam_front_end(std::make_unique<RecordingSlam>(seen));
  fusion::PerceptionFocus focus;
  focus.slam = true;
  pipelines.set_focus(focus);
  VideoFrame frame;
  frame.camera = CameraId::Front;
  frame.bgr = cv::Mat(360, 640, CV_8UC3, cv::Scalar(90, 90, 90));
  frame.t = 0.05;
  pipelines.on_video(frame);  // no navdata yet: no attitude
  // 15 Hz navdata (received at t, measured navdata_delay_s earlier), the nose going down 0.1 rad/s.
  const estimation::EstimatorConfig config;
  for (int i = 0; i <= 15; ++i) {
    NavdataSample n;
    n.t = 0.1 + i / 15.0;
    n.roll_rad = -0.03;
    n.pitch_rad = 0.1 * (n.t - config.navdata_delay_s);
    pipelines.on_navdata(n);
  }
  frame.t = 0.9;
  pipelines.on_video(frame);
  REQUIRE(seen.size() == 2);
  CHECK_FALSE(seen[0]);
  REQUIRE(seen[1]);
  // The frame was captured video_delay_s before it arrived.
  const Eigen::Vector3d expected = slam::gravity_down_in_camera(-0.03, 0.1 * (0.9 - config.video_delay_s), T_body_cam_front());
  CHECK((*seen[1] - expected).norm() < 1e-9);
}
