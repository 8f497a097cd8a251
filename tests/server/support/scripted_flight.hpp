#pragma once
// Test double of the FlightService: records requests, answers with scripted verdicts, and lets the
// test publish frames and events as the runtime would. Tests only.
#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "server/lab/flight_service.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_encoder.hpp"

namespace labo::test {

class ScriptedFlight final : public FlightService {
 public:
  void set_sink(FlightEventSink* sink) override {
    std::lock_guard lock(mutex_);
    sink_ = sink;
  }
  CommandVerdict request(const MissionCommand& command) override {
    std::lock_guard lock(mutex_);
    requests.push_back(command);
    if (command.kind == MissionCommandKind::Inspect && command.instrument != "oscilloscope")
      return {false, "no instrument '" + command.instrument + "'"};
    if (command.kind == MissionCommandKind::Land || command.kind == MissionCommandKind::Stop ||
        command.kind == MissionCommandKind::EmergencyStop)
      telemetry_.flying = false;
    if (command.kind == MissionCommandKind::Takeoff) telemetry_.flying = true;
    return {true, "started " + to_string(command.kind)};
  }
  FlightTelemetry telemetry() const override {
    std::lock_guard lock(mutex_);
    return telemetry_;
  }
  std::vector<InstrumentSummary> instruments() const override { return {{"oscilloscope", "Oscilloscope", 0.3, 0.15, 2.0, 0.5}}; }
  void land_and_stop(double) override { landed_on_shutdown = true; }

  void publish_frame(std::uint32_t number, int bytes_of_noise = 0) {
    cv::Mat img(360, 640, CV_8UC3, cv::Scalar(40, 80, 120));
    if (bytes_of_noise > 0) cv::randu(img, 0, 255);
    const WireFrame f = encoder_.encode(img, number, 1.0e12, CameraId::Front);
    std::lock_guard lock(mutex_);
    if (sink_) sink_->on_frame(f);
  }
  // An access unit of `bytes` filler bytes (not real H.264: the server does not look inside) with
  // a one-line geometry message naming its frame.
  void publish_access_unit(std::uint32_t number, bool keyframe, std::size_t bytes = 2000) {
    filler_.assign(bytes, static_cast<std::uint8_t>(number));
    WireAccessUnit unit = packer_.pack({0, CameraId::Front, number, keyframe, 640, 360, filler_}, 1.0e12);
    unit.geometry = std::make_shared<const std::string>(R"({"type":"overlay","frame":)" + std::to_string(number) + "}");
    std::lock_guard lock(mutex_);
    if (sink_) sink_->on_access_unit(unit);
  }
  std::size_t access_unit_buffers() const { return packer_.buffers(); }
  void publish_event(const FlightEvent& e) {
    std::lock_guard lock(mutex_);
    if (sink_) sink_->on_flight_event(e);
  }
  std::vector<MissionCommand> requests_seen() {
    std::lock_guard lock(mutex_);
    return requests;
  }

  std::vector<MissionCommand> requests;
  bool landed_on_shutdown = false;

 private:
  mutable std::mutex mutex_;
  FlightEventSink* sink_ = nullptr;
  FlightTelemetry telemetry_;
  FrameEncoder encoder_{70};
  AccessUnitPacker packer_;
  std::vector<std::uint8_t> filler_;
};

}  // namespace labo::test
