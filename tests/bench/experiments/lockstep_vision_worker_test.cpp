#include "bench/experiments/lockstep_vision_worker.hpp"

#include <catch2/catch.hpp>
#include <vector>
#include "tests/support/instrument_job.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

// A front-end that reports the method it was built with.
class MethodFrontEnd final : public fusion::TargetFrontEnd {
 public:
  explicit MethodFrontEnd(std::string method) { o_.method = std::move(method); }
  const fusion::TargetObservation& process(const cv::Mat&, Seconds t, std::optional<double>) override {
    o_.state = fusion::TrackState::Tracking;
    o_.t = t;
    return o_;
  }
  void reset() override {}
  fusion::TargetObservation o_;
};

// Pipelines that run one instrument front-end per frame and record the frame times applied.
class RecordingPipelines final : public fusion::LocalizationPipelines {
 public:
  explicit RecordingPipelines(fusion::TargetFrontEnd& fe) : fe_(fe) {}
  void on_navdata(const NavdataSample&) override {}
  void on_command(const MoveCommand&, Seconds) override {}
  void on_video(const VideoFrame&) override {}
  bool prepare_vision(const VideoFrame& frame, fusion::VisionJob& job) override { return test::instrument_job(frame, fe_, job); }
  void apply_vision(const fusion::VisionResults& r) override { applied->push_back(r.t); }
  void set_focus(const fusion::PerceptionFocus&) override {}
  void reset(const Eigen::Isometry3d&, Seconds) override {}
  void start_at_first_navdata(const Eigen::Isometry3d&) override {}
  fusion::PoseEstimate predict(Seconds t) const override { return {.t = t}; }
  fusion::TargetObservation instrument() const override { return {}; }
  fusion::TargetObservation platform() const override { return {}; }
  fusion::TargetObservation face() const override { return {}; }
  fusion::SlamSummary slam() const override { return {}; }

  std::shared_ptr<std::vector<Seconds>> applied = std::make_shared<std::vector<Seconds>>();

 private:
  fusion::TargetFrontEnd& fe_;
};

VideoFrame frame_at(Seconds t) {
  VideoFrame f;
  f.t = t;
  f.bgr = cv::Mat(36, 64, CV_8UC1, cv::Scalar(7));
  return f;
}

}  // namespace

TEST_CASE("lockstep vision worker: results wait for the modelled time, and a busy worker keeps only the newest frame") {
  MethodFrontEnd detector("template");
  auto pipelines = std::make_unique<RecordingPipelines>(detector);
  const auto applied = pipelines->applied;
  control::FlightStack stack(control::FlightStackSetup{}, std::move(pipelines));
  VisionLatencyModel model;
  model.template_detection_ms = 18.3;  // a slow search, longer than the frames' spacing below
  LockstepVisionWorker worker(stack, model);

  worker.on_frame(frame_at(0.00), 0.00);  // a template search: 18.3 + 0.2 ms
  worker.advance(0.0180);
  CHECK(applied->empty());
  worker.on_frame(frame_at(0.01), 0.010);  // busy: waits
  worker.on_frame(frame_at(0.02), 0.015);  // replaces it
  worker.advance(0.0186);
  REQUIRE(applied->size() == 1);
  CHECK(applied->front() == 0.00);
  worker.advance(0.0186 + 0.0184);  // the newest frame started at 0.0186
  CHECK(applied->size() == 1);
  worker.advance(0.0186 + 0.0186);
  REQUIRE(applied->size() == 2);
  CHECK(applied->back() == 0.02);
  CHECK(worker.stats().frames_in == 3);
  CHECK(worker.stats().frames_to_vision == 2);
  CHECK(worker.stats().frames_skipped == 1);
}

TEST_CASE("lockstep vision worker: a frame's modelled time is the sum of what its vision did") {
  const VisionLatencyModel m;
  fusion::VisionResults r;
  CHECK(m.latency_of(r) == Approx(m.handoff_ms / 1000.0));
  r.has_slam = true;
  r.slam.summary.state = fusion::SlamState::Good;
  r.has_instrument = true;
  r.instrument.method = "ic";
  CHECK(m.latency_of(r) == Approx((m.handoff_ms + m.slam_ms + m.planar_tracking_ms) / 1000.0));
  r.instrument.method = "features";
  CHECK(m.latency_of(r) == Approx((m.handoff_ms + m.slam_ms + m.feature_detection_ms) / 1000.0));
  r.instrument.method = "none";  // a search that found nothing costs a search
  CHECK(m.latency_of(r) == Approx((m.handoff_ms + m.slam_ms + m.feature_detection_ms) / 1000.0));
  r.slam.summary.state = fusion::SlamState::Off;  // paused on a bottom frame: nothing to run
  r.has_instrument = false;
  r.has_platform = true;
  r.platform.method = "ic";
  r.has_face = true;
  CHECK(m.latency_of(r) == Approx((m.handoff_ms + m.platform_tracking_ms + m.face_ms) / 1000.0));
}
