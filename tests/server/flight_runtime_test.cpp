#include <catch2/catch.hpp>
#include <atomic>
#include <mutex>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "server/runtime/flight_runtime.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/fake_drone.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;

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
  bool wants_low_rendition() const override { return low; }
  bool take_low_keyframe_request() override { return low_keyframe.exchange(false); }
  std::mutex mutex;
  std::vector<WireFrame> frames;
  std::vector<WireAccessUnit> units;
  std::vector<FlightEvent> events;
  std::atomic<bool> jpeg = true, h264 = false, low = false, low_keyframe = false;
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
  // The timeline is built from the core's progress at every tick: stages begin as the mission's do.
  const MissionTimeline timeline = runtime.telemetry().timeline;
  CHECK(timeline.mission == "inspect");
  REQUIRE(timeline.stages.size() >= 2);
  CHECK(timeline.stages[0].name == "take off");
  CHECK(timeline.stages[0].ended);
  CHECK(timeline.stages[1].index == 2);
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

TEST_CASE("web: the flight runtime encodes the shared low rendition only while a viewer needs it, an IDR when asked") {
  SteadyClock clock;
  FakeDroneLink link;
  link.set_textured(true);
  ScriptedCore core(5.0);
  CapturingSink sink;
  sink.jpeg = false;
  FlightRuntime runtime(link, core, clock, {}, Logger("test", LogLevel::Warn));
  runtime.set_sink(&sink);
  runtime.start();
  const auto deliver = [&](std::uint32_t from, std::uint32_t to) {
    for (std::uint32_t n = from; n < to; ++n) {
      link.deliver_frame(n, clock.now());
      std::this_thread::sleep_for(std::chrono::milliseconds(33));
    }
  };
  deliver(0, 10);
  {
    std::lock_guard lock(sink.mutex);
    CHECK(sink.units.empty());  // nobody needs it: nothing encoded
  }
  sink.low = true;
  deliver(10, 50);
  sink.low_keyframe = true;
  deliver(50, 60);
  sink.low = false;
  deliver(60, 70);
  runtime.land_and_stop(0.5);
  std::lock_guard lock(sink.mutex);
  REQUIRE(sink.units.size() >= 30);
  ardrone2::H264Decoder decoder;
  cv::Mat bgr;
  int decoded = 0, keyframes_after_request = 0;
  for (const WireAccessUnit& u : sink.units) {
    CHECK(u.rendition == Rendition::Low);
    CHECK(u.frame_number >= 10);
    CHECK(u.frame_number < 60);
    const auto h = AccessUnitHeader::read(*u.wire);
    REQUIRE(h);
    CHECK(h->rendition == Rendition::Low);
    CHECK(h->width == 640);
    REQUIRE(u.geometry);
    CHECK(nlohmann::json::parse(*u.geometry)["frame"] == u.frame_number);  // the source frame's geometry
    const std::span<const std::uint8_t> annexb(reinterpret_cast<const std::uint8_t*>(u.wire->data()) + AccessUnitHeader::kSize,
                                               h->annexb_bytes);
    decoded += decoder.decode(annexb, bgr) == ardrone2::DecodeStatus::Decoded;
    keyframes_after_request += u.keyframe && u.frame_number >= 50 && u.frame_number < 55;
  }
  CHECK(sink.units.front().keyframe);  // the encoder starts with an IDR
  CHECK(keyframes_after_request >= 1);  // frame 50-54: the IDR asked for (the 30-frame cadence has none there)
  CHECK(decoded >= static_cast<int>(sink.units.size()) - 1);
}

TEST_CASE("web: the bottom camera: streamed when the drone has one, refused with the reason when it has not") {
  SteadyClock clock;
  FakeDroneLink link;
  ScriptedCore core(5.0);
  int asked_kbps = 0;
  FlightRuntimeOptions ardrone;
  ardrone.video = {"AR.Drone 2.0", true, "", true, 4000, 250, 4000};
  ardrone.set_video_bitrate = [&](int kbps) { asked_kbps = kbps; };
  {
    FlightRuntime runtime(link, core, clock, ardrone, Logger("test", LogLevel::Warn));
    runtime.start();
    CHECK(runtime.request({MissionCommandKind::SelectCamera, "", 0, CameraId::Bottom}).accepted);
    for (int i = 0; i < 100 && link.camera() != CameraId::Bottom; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    CHECK(link.camera() == CameraId::Bottom);
    CHECK(runtime.request({MissionCommandKind::SelectCamera, "", 0, CameraId::Front}).accepted);
    for (int i = 0; i < 100 && link.camera() != CameraId::Front; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    CHECK(link.camera() == CameraId::Front);
    CHECK(runtime.set_video_bitrate(2000).accepted);
    CHECK(asked_kbps == 2000);
    CHECK(runtime.video_capabilities().bitrate_kbps == 2000);
    const CommandVerdict too_high = runtime.set_video_bitrate(4001);
    CHECK_FALSE(too_high.accepted);
    CHECK(too_high.reason == "AR.Drone 2.0 video bit rate: 250..4000 kbit/s expected, got 4001");
    CHECK(asked_kbps == 2000);
    runtime.land_and_stop(0.5);
  }
  FlightRuntimeOptions tello;
  tello.video = {"Tello", false, "a Tello has one camera, looking forward: there is no bottom camera to stream", false, 0, 0, 0};
  FlightRuntime runtime(link, core, clock, tello, Logger("test", LogLevel::Warn));
  runtime.start();
  const CommandVerdict refused = runtime.request({MissionCommandKind::SelectCamera, "", 0, CameraId::Bottom});
  CHECK_FALSE(refused.accepted);
  CHECK(refused.reason == "select_camera: a Tello has one camera, looking forward: there is no bottom camera to stream");
  CHECK(runtime.request({MissionCommandKind::SelectCamera, "", 0, CameraId::Front}).accepted);  // its one camera
  CHECK(runtime.set_video_bitrate(2000).reason == "Tello: the link cannot ask the drone for a video bit rate");
  runtime.land_and_stop(0.5);
  CHECK(link.camera() == CameraId::Front);
}
