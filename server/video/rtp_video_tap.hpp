#pragma once
// A FlightService that is another one with its H.264 access units also forwarded as RTP
// (RtpVideoForwarder): `serve --rtp-video HOST:PORT` puts it between the drone's runtime and the web
// server, so the lab's WebSocket fan-out is unchanged and the media server gets every unit, whether
// or not anyone watches the WebSocket's H.264 path (the drone's own stream only: the shared low
// rendition is for the WebSocket's slow viewers), and with a GeometryForwarder each unit's geometry
// too, just before the unit (the page has it when the frame arrives). Everything else passes
// through untouched.
#include <mutex>

#include "server/lab/flight_service.hpp"
#include "server/video/geometry_forwarder.hpp"
#include "server/video/rtp_video_forwarder.hpp"

namespace labo::server {

class RtpVideoTap final : public FlightService, private FlightEventSink {
 public:
  RtpVideoTap(FlightService& inner, RtpVideoForwarder& forwarder, GeometryForwarder* geometry = nullptr);
  ~RtpVideoTap() override;

  void set_sink(FlightEventSink* sink) override;
  CommandVerdict request(const MissionCommand& command) override { return inner_.request(command); }
  FlightTelemetry telemetry() const override { return inner_.telemetry(); }
  std::vector<InstrumentSummary> instruments() const override { return inner_.instruments(); }
  LabOutline lab_outline() const override { return inner_.lab_outline(); }
  CommandVerdict add_instrument(const lab::InstrumentSpec& spec) override { return inner_.add_instrument(spec); }
  CommandVerdict remove_instrument(const std::string& id) override { return inner_.remove_instrument(id); }
  CommandVerdict set_down_on_platform() override { return inner_.set_down_on_platform(); }
  void land_and_stop(double timeout_s) override { inner_.land_and_stop(timeout_s); }
  RuntimeTimingSummary timing() const override { return inner_.timing(); }
  VideoCapabilities video_capabilities() const override { return inner_.video_capabilities(); }
  CommandVerdict set_video_bitrate(int kbps) override { return inner_.set_video_bitrate(kbps); }

 private:
  void on_frame(const WireFrame& frame) override;
  void on_access_unit(const WireAccessUnit& unit) override;
  void on_reading_view(std::shared_ptr<const std::string> view) override;
  void on_flight_event(const FlightEvent& event) override;
  bool wants_jpeg() const override;
  bool wants_access_units() const override { return true; }  // the media server always does
  bool wants_reading_view() const override;
  bool wants_low_rendition() const override;
  bool take_low_keyframe_request() override;

  FlightService& inner_;
  RtpVideoForwarder& forwarder_;
  GeometryForwarder* geometry_;
  // The outer sink (the web server's lab) may be set and cleared while the runtime's threads call in.
  mutable std::mutex sink_mutex_;
  FlightEventSink* sink_ = nullptr;
};

}  // namespace labo::server
