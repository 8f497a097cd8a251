#include "server/runtime/vision_worker.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <thread>

#include "server/runtime/flight_runtime.hpp"
#include "tests/server/support/fake_drone.hpp"
#include "tests/support/instrument_job.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::test;
using namespace labo::server::test;

namespace {

// A front-end that holds every frame until the test releases it, and counts its frames.
class GatedFrontEnd final : public fusion::TargetFrontEnd {
 public:
  const fusion::TargetObservation& process(const cv::Mat& gray, Seconds t, std::optional<double>) override {
    std::unique_lock lock(mutex_);
    ++entered_;
    cv_.notify_all();
    cv_.wait(lock, [&] { return open_; });
    observation_.state = gray.empty() ? fusion::TrackState::Lost : fusion::TrackState::Tracking;
    observation_.t = t;
    observation_.method = "template";
    return observation_;
  }
  void reset() override {}
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    cv_.notify_all();
  }
  bool wait_entered(int n) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, std::chrono::seconds(10), [&] { return entered_ >= n; });
  }
  int entered() {
    std::lock_guard lock(mutex_);
    return entered_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool open_ = false;
  int entered_ = 0;
  fusion::TargetObservation observation_;
};

fusion::VisionJob job_for(fusion::TargetFrontEnd& fe, Seconds t) {
  fusion::VisionJob job;
  job.t = t;
  job.gray = cv::Mat(36, 64, CV_8UC1, cv::Scalar(100));
  job.instrument = &fe;
  job.instrument_id = "oscilloscope";
  return job;
}

// A core whose vision runs through the gated front-end, counting ticks and applied results.
class GatedVisionCore final : public FlightCore {
 public:
  explicit GatedVisionCore(GatedFrontEnd& fe) : fe_(fe) {}
  void on_navdata(const NavdataSample&) override {}
  void on_video(const VideoFrame&) override {}
  bool prepare_vision(const VideoFrame& frame, fusion::VisionJob& job) override { return labo::test::instrument_job(frame, fe_, job); }
  void apply_vision(const fusion::VisionResults& r) override {
    if (r.has_instrument && r.instrument.state == fusion::TrackState::Tracking) ++applied;
  }
  void on_link_state(LinkState, Seconds) override {}
  FlightAction tick(Seconds) override {
    ++ticks;
    return {};
  }
  CommandVerdict request(const MissionCommand&, Seconds) override { return {true, ""}; }
  FlightSnapshot status() override { return {}; }
  std::vector<InstrumentSummary> instruments() const override { return {}; }

  std::atomic<int> ticks{0}, applied{0};

 private:
  GatedFrontEnd& fe_;
};

bool eventually(const std::function<bool()>& condition) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace

TEST_CASE("vision worker: runs one job at a time and hands its results back by swap") {
  GatedFrontEnd fe;
  std::promise<void> done;
  VisionWorker worker([&] { done.set_value(); });
  CHECK(worker.idle());
  fusion::VisionJob job = job_for(fe, 1.5);
  worker.submit(job);
  CHECK_FALSE(worker.idle());
  REQUIRE(fe.wait_entered(1));
  fusion::VisionResults results;
  double run_ms = -1;
  CHECK_FALSE(worker.take(results, run_ms));  // still running
  fusion::VisionJob second = job_for(fe, 2.0);
  CHECK_THROWS_AS(worker.submit(second), std::logic_error);
  fe.open();
  REQUIRE(done.get_future().wait_for(std::chrono::seconds(10)) == std::future_status::ready);
  REQUIRE(worker.take(results, run_ms));
  CHECK(worker.idle());
  CHECK(results.t == 1.5);
  CHECK(results.has_instrument);
  CHECK(results.instrument_id == "oscilloscope");
  CHECK(results.instrument.state == fusion::TrackState::Tracking);
  CHECK(results.detected());
  CHECK(run_ms >= 0);
}

TEST_CASE("vision worker: a front-end that throws yields an empty result with the reason") {
  struct Throwing final : fusion::TargetFrontEnd {
    const fusion::TargetObservation& process(const cv::Mat&, Seconds, std::optional<double>) override {
      throw std::runtime_error("frame of the wrong size");
    }
    void reset() override {}
  } fe;
  std::promise<void> done;
  VisionWorker worker([&] { done.set_value(); });
  fusion::VisionJob job;
  job.instrument = &fe;
  worker.submit(job);
  REQUIRE(done.get_future().wait_for(std::chrono::seconds(10)) == std::future_status::ready);
  fusion::VisionResults results;
  double run_ms = 0;
  REQUIRE(worker.take(results, run_ms));
  CHECK_FALSE(results.has_instrument);
  CHECK(results.failure == "frame of the wrong size");
}

TEST_CASE("web: control keeps ticking while a frame's vision is stuck, and the newest frame goes next") {
  SteadyClock clock;
  FakeDroneLink link;
  GatedFrontEnd fe;
  GatedVisionCore core(fe);
  FlightRuntime runtime(link, core, clock, {}, Logger("test", LogLevel::Warn));
  runtime.start();
  link.deliver_frame(0, clock.now());
  REQUIRE(fe.wait_entered(1));  // the worker holds frame 0
  const int ticks_before = core.ticks.load();
  for (std::uint32_t n = 1; n <= 5; ++n) link.deliver_frame(n, clock.now());
  // Vision is blocked, yet the flight thread goes on ticking (at 50 Hz, 10 ticks are 0.2 s).
  CHECK(eventually([&] { return core.ticks.load() >= ticks_before + 10; }));
  CHECK(fe.entered() == 1);
  fe.open();
  // Frame 0's result is applied; of frames 1-5 only the newest reaches the worker.
  CHECK(eventually([&] { return core.applied.load() >= 2; }));
  runtime.land_and_stop(0.2);
  const RuntimeTimingSummary timing = runtime.timing();
  CHECK(timing.frames_in == 6);
  CHECK(timing.frames_to_vision == 2);
  CHECK(timing.frames_skipped == 4);
  CHECK(timing.vision_latency_ms.count == 2);
  // At least the 10 ticks above; their intervals are one fewer when the first tick came after frame 0
  // reached the worker (the runtime counts an interval from the second tick on).
  CHECK(timing.tick_interval_ms.count >= 9);
}
