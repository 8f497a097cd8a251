#pragma once
// Test double of the FlightService: records requests, answers with scripted verdicts, and lets the
// test publish frames and events as the runtime would. Tests only.
#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "server/lab/flight_service.hpp"
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
    if (command.kind == MissionCommandKind::Land || command.kind == MissionCommandKind::EmergencyStop) telemetry_.flying = false;
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
};

}  // namespace labo::test
