#pragma once
// Test double of the FlightService: records requests, answers with scripted verdicts, and lets the
// test publish frames and events as the runtime would. Tests only.
#include <algorithm>
#include <mutex>
#include <opencv2/core.hpp>
#include <vector>

#include "server/lab/flight_service.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_encoder.hpp"

namespace labo::server::test {

// A room 8 x 6 m with one bench 0.9 m high along its east wall, as the lab file would state it.
inline LabOutline scripted_lab_outline() {
  LabOutline o;
  o.known = true;
  o.room = {"room", -1.5, -3.0, 6.5, 3.0, 0.0, 3.0};
  o.benches = {{"bench_east", 5.7, -2.2, 6.5, 1.2, 0.0, 0.9}};
  o.platform = {"platform", -0.3, -0.3, 0.3, 0.3, 0.0, 0.1};
  return o;
}

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
  // Changes what telemetry() answers from now on, as the runtime's control tick would.
  template <typename Edit>
  void edit_telemetry(Edit edit) {
    std::lock_guard lock(mutex_);
    edit(telemetry_);
  }
  std::vector<InstrumentSummary> instruments() const override {
    std::lock_guard lock(mutex_);
    return instruments_;
  }
  LabOutline lab_outline() const override { return scripted_lab_outline(); }
  // Accepts a new id (the flight software's own checks are tested in tests/control); an instrument
  // being "inspected" may not be removed.
  CommandVerdict add_instrument(const lab::InstrumentSpec& spec) override {
    std::lock_guard lock(mutex_);
    for (const auto& i : instruments_)
      if (i.id == spec.id) return {false, "instrument '" + spec.id + "' is in the lab already"};
    instruments_.push_back({spec.id, spec.name, spec.width_m, spec.height_m, spec.T_world_object.translation().x(),
                            spec.T_world_object.translation().y()});
    placed.push_back(spec);
    return {true, "instrument '" + spec.id + "' placed in the lab"};
  }
  CommandVerdict remove_instrument(const std::string& id) override {
    std::lock_guard lock(mutex_);
    if (id == inspecting) return {false, "instrument '" + id + "' is being inspected: stop the mission first"};
    const auto it = std::find_if(instruments_.begin(), instruments_.end(), [&](const auto& i) { return i.id == id; });
    if (it == instruments_.end()) return {false, "no instrument '" + id + "' in the lab"};
    instruments_.erase(it);
    return {true, "instrument '" + id + "' removed from the lab"};
  }
  // As the flight software: refused in flight; accepted on the ground, the place confirmed.
  CommandVerdict set_down_on_platform() override {
    std::lock_guard lock(mutex_);
    if (telemetry_.flying) return {false, "set-down: the drone is flying (flying); land it, then set it on its platform"};
    telemetry_.unobserved_flight_s = 0;
    ++set_downs;
    return {true, "the drone was set on its platform: its place is the base's again"};
  }
  void land_and_stop(double) override { landed_on_shutdown = true; }
  VideoCapabilities video_capabilities() const override {
    std::lock_guard lock(mutex_);
    return video;
  }
  CommandVerdict set_video_bitrate(int kbps) override {
    std::lock_guard lock(mutex_);
    video.bitrate_kbps = kbps;
    return {true, "asked for " + std::to_string(kbps) + " kbit/s"};
  }
  // Like an AR.Drone 2.0 unless the test plays another drone (set before the server starts).
  VideoCapabilities video{"scripted AR.Drone", true, "", true, 4000, 250, 4000};

  void publish_frame(std::uint32_t number, int bytes_of_noise = 0) {
    cv::Mat img(360, 640, CV_8UC3, cv::Scalar(40, 80, 120));
    if (bytes_of_noise > 0) cv::randu(img, 0, 255);
    const WireFrame f = encoder_.encode(img, number, 1.0e12, CameraId::Front);
    std::lock_guard lock(mutex_);
    if (sink_) sink_->on_frame(f);
  }
  // An access unit of `bytes` filler bytes (not real H.264: the server does not look inside) with
  // a one-line geometry message naming its frame.
  void publish_access_unit(std::uint32_t number, bool keyframe, std::size_t bytes = 2000,
                           Rendition rendition = Rendition::Source) {
    filler_.assign(bytes, static_cast<std::uint8_t>(number));
    WireAccessUnit unit = packer_.pack({0, CameraId::Front, number, keyframe, 640, 360, filler_}, 1.0e12, rendition);
    unit.geometry = std::make_shared<const std::string>(R"({"type":"overlay","frame":)" + std::to_string(number) + "}");
    std::lock_guard lock(mutex_);
    if (sink_) sink_->on_access_unit(unit);
  }
  std::size_t access_unit_buffers() const { return packer_.buffers(); }
  // What the runtime's video thread asks before each frame: run the low rendition's encoder, and
  // make this frame an IDR.
  bool low_rendition_wanted() {
    std::lock_guard lock(mutex_);
    return sink_ && sink_->wants_low_rendition();
  }
  bool take_low_keyframe_request() {
    std::lock_guard lock(mutex_);
    return sink_ && sink_->take_low_keyframe_request();
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
  int set_downs = 0;  // accepted set_down_on_platform() calls
  std::vector<lab::InstrumentSpec> placed;  // what add_instrument accepted
  std::string inspecting;              // an instrument remove_instrument refuses

 private:
  mutable std::mutex mutex_;
  FlightEventSink* sink_ = nullptr;
  FlightTelemetry telemetry_;
  std::vector<InstrumentSummary> instruments_{{"oscilloscope", "Oscilloscope", 0.3, 0.15, 2.0, 0.5}};
  FrameEncoder encoder_{70};
  AccessUnitPacker packer_;
  std::vector<std::uint8_t> filler_;
};

}  // namespace labo::server::test
