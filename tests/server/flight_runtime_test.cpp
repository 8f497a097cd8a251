#include <catch2/catch.hpp>
#include <mutex>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "server/runtime/flight_runtime.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/fake_drone.hpp"

using namespace labo;
using namespace labo::test;

namespace {
struct CapturingSink final : FlightEventSink {
  void on_frame(const WireFrame& f) override {
    std::lock_guard lock(mutex);
    frames.push_back(f);
  }
  void on_access_unit(const WireAccessUnit& u) override {
    std::lock_guard lock(mutex);
    units.push_back(u);
  }
  void on_flight_event(const FlightEvent& e) override {
    std::lock_guard lock(mutex);
    events.push_back(e);
  }
  bool wants_jpeg() const override { return jpeg; }
  bool wants_access_units() const override { return h264; }
  std::mutex mutex;
  std::vector<WireFrame> frames;
  std::vector<WireAccessUnit> units;
  std::vector<FlightEvent> events;
  bool jpeg = true, h264 = false;
};
}  // namespace

TEST_CASE("web: the flight runtime annotates and encodes frames, and passes stage changes on") {
  SteadyClock clock;
  FakeDroneLink link;
  ScriptedCore core(0.2);
  CapturingSink sink;
  FlightRuntime runtime(link, core, clock, {}, Logger("test", LogLevel::Warn));
  runtime.set_sink(&sink);
  runtime.start();
  CHECK(runtime.request({MissionCommandKind::Inspect, "oscilloscope", 5}).accepted);
  CHECK_FALSE(runtime.request({MissionCommandKind::Inspect, "toaster", 5}).accepted);
  for (std::uint32_t n = 0; n < 20; ++n) {
    link.deliver_frame(n, clock.now());
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
  runtime.land_and_stop(1.0);
  std::lock_guard lock(sink.mutex);
  REQUIRE(sink.frames.size() >= 10);
  const WireFrame& last = sink.frames.back();
  const auto header = FrameHeader::read(*last.wire);
  REQUIRE(header);
  CHECK(header->frame_number == last.frame_number);
  CHECK(std::abs(header->capture_unix_ms / 1000.0 - std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count()) < 5.0);
  // Which stage the scripted mission is in when a frame is drawn depends on thread timing (a loaded
  // machine lags), so look for a frame drawn while the panel was tracked: the homography source's
  // border is blue (BGR ~ (255, 96, 16)) and the panel outline cyan.
  int annotated = 0;
  for (const WireFrame& f : sink.frames) {
    const std::vector<std::uint8_t> jpeg(f.wire->begin() + FrameHeader::kSize, f.wire->end());
    const cv::Mat decoded = cv::imdecode(jpeg, cv::IMREAD_COLOR);
    REQUIRE(decoded.cols == 640);
    const cv::Vec3b border = decoded.at<cv::Vec3b>(200, 1);
    const cv::Vec3b outline = decoded.at<cv::Vec3b>(100, 300);
    const bool blue_border = border[0] > 180 && border[2] < 90;
    const bool cyan_outline = outline[0] > 180 && outline[1] > 180;
    annotated += blue_border && cyan_outline;
  }
  CHECK(annotated >= 1);
  int stages = 0;
  for (const auto& e : sink.events) stages += e.kind == "stage";
  CHECK(stages >= 3);
  CHECK(core.frames.load() > 0);
}

TEST_CASE("web: an emergency stop reaches the drone before the flight software answers") {
  SteadyClock clock;
  FakeDroneLink link;
  ScriptedCore core(1.0, 0.3);  // the flight software takes 300 ms per request
  FlightRuntime runtime(link, core, clock, {}, Logger("test", LogLevel::Warn));
  runtime.start();
  const auto start = std::chrono::steady_clock::now();
  const CommandVerdict v = runtime.request({MissionCommandKind::EmergencyStop, "", 0});
  const auto answered = std::chrono::steady_clock::now();
  CHECK(v.accepted);
  REQUIRE(link.emergencies.load() == 1);
  CHECK(std::chrono::duration<double>(link.emergency_at - start).count() < 0.05);
  CHECK(std::chrono::duration<double>(answered - start).count() >= 0.25);
  runtime.land_and_stop(0.5);
}

TEST_CASE("web: the flight runtime passes the drone's access units on as they came, with their frame's geometry") {
  SteadyClock clock;
  FakeDroneLink link;
  link.set_h264(true);
  ScriptedCore core(10.0);
  CapturingSink sink;
  sink.jpeg = false;  // nobody watches JPEG: nothing is encoded
  sink.h264 = true;
  FlightRuntime runtime(link, core, clock, {}, Logger("test", LogLevel::Warn));
  runtime.set_sink(&sink);
  runtime.start();
  CHECK(runtime.request({MissionCommandKind::Inspect, "oscilloscope", 5}).accepted);
  for (std::uint32_t n = 0; n < 20; ++n) {
    link.deliver_frame(n, clock.now());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  runtime.land_and_stop(1.0);
  std::lock_guard lock(sink.mutex);
  CHECK(sink.frames.empty());
  REQUIRE(sink.units.size() == 20);  // every one, in order: none may be skipped before the viewers
  for (std::uint32_t n = 0; n < 20; ++n) {
    const WireAccessUnit& u = sink.units[n];
    const auto header = AccessUnitHeader::read(*u.wire);
    REQUIRE(header);
    CHECK(header->frame_number == n);
    CHECK(header->keyframe == (n % 15 == 0));
    CHECK(header->width == 640);
    CHECK(header->capture_unix_ms == u.capture_unix_ms);
    // The Annex-B bytes start with a start code; the geometry names the same frame and time.
    CHECK(u.wire->substr(AccessUnitHeader::kSize, 4) == std::string("\0\0\0\1", 4));
    const auto geometry = nlohmann::json::parse(*u.geometry);
    CHECK(geometry["frame"] == n);
    CHECK(geometry["capture_ms"].get<double>() == Approx(u.capture_unix_ms).margin(0.001));
  }
  // Once the scripted mission reported its panel, the geometry carries it.
  const auto last = nlohmann::json::parse(*sink.units.back().geometry);
  CHECK(last["panel"]["corners"][0] == nlohmann::json::array({220.0, 100.0}));
  CHECK(last["source_colour"] == "#1060ff");
}
