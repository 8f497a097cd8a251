#include "server/video/rtp_video_tap.hpp"

namespace labo::server {

RtpVideoTap::RtpVideoTap(FlightService& inner, RtpVideoForwarder& forwarder, GeometryForwarder* geometry)
    : inner_(inner), forwarder_(forwarder), geometry_(geometry) {
  inner_.set_sink(this);
}

RtpVideoTap::~RtpVideoTap() { inner_.set_sink(nullptr); }

void RtpVideoTap::set_sink(FlightEventSink* sink) {
  std::lock_guard lock(sink_mutex_);
  sink_ = sink;
}

void RtpVideoTap::on_frame(const WireFrame& frame) {
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_frame(frame);
}

void RtpVideoTap::on_access_unit(const WireAccessUnit& unit) {
  if (unit.rendition == Rendition::Source) {
    if (geometry_ && unit.geometry) geometry_->forward(unit.frame_number, *unit.geometry);
    forwarder_.forward(unit);
  }
  std::lock_guard lock(sink_mutex_);
  if (sink_ && sink_->wants_access_units()) sink_->on_access_unit(unit);
}

void RtpVideoTap::on_reading_view(std::shared_ptr<const std::string> view) {
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_reading_view(std::move(view));
}

void RtpVideoTap::on_flight_event(const FlightEvent& event) {
  std::lock_guard lock(sink_mutex_);
  if (sink_) sink_->on_flight_event(event);
}

bool RtpVideoTap::wants_jpeg() const {
  std::lock_guard lock(sink_mutex_);
  return sink_ && sink_->wants_jpeg();
}

bool RtpVideoTap::wants_reading_view() const {
  std::lock_guard lock(sink_mutex_);
  return sink_ && sink_->wants_reading_view();
}

bool RtpVideoTap::wants_low_rendition() const {
  std::lock_guard lock(sink_mutex_);
  return sink_ && sink_->wants_low_rendition();
}

bool RtpVideoTap::take_low_keyframe_request() {
  std::lock_guard lock(sink_mutex_);
  return sink_ && sink_->take_low_keyframe_request();
}

}  // namespace labo::server
