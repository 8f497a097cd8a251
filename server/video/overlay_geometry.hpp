#pragma once
// The overlays of one frame as data, for viewers that draw them themselves (the H.264 path): one
// JSON text message per access unit, stamped with the frame's number and capture time, built once
// into a pooled buffer and shared by every H.264 viewer (no allocation per frame in steady state).
//   {"type":"overlay","frame":N,"capture_ms":T,"camera":"front","width":640,"height":360,
//    "source":"homography","source_colour":"#1060ff",
//    "panel":{"corners":[[x,y]x4],"axes":{"o":[x,y],"x":..,"y":..,"z":..}|null,"measured_ms":T}|null,
//    "platform":{...same...}|null,
//    "face":{"points":[[x,y]...],"edges":[[i,j]...],"axes":..|null,"measured_ms":T}|null,
//    "hud":{"battery_percent","altitude_m","yaw_deg","link_quality","mission","stage"}}
// Pixels of the frame the geometry was measured on (`measured_ms`, the newest vision result when
// the frame went out: the same geometry the JPEG path draws into that frame). A coordinate that is
// not finite is null.
#include <cstdint>
#include <memory>
#include <string>

#include "server/lab/flight_service.hpp"
#include "server/video/overlay_model.hpp"
#include "server/video/wire_buffer_pool.hpp"

namespace labo::server {

struct FrameStamp {
  std::uint32_t frame_number = 0;
  double capture_unix_ms = 0;
  CameraId camera = CameraId::Front;
  int width = 0, height = 0;
};

class OverlayGeometryWriter {
 public:
  OverlayGeometryWriter() : pool_(32, 4096) {}
  // Times in `overlay` are the link clock's seconds; `clock_to_unix_s` maps them to Unix time.
  std::shared_ptr<const std::string> write(const OverlayModel& overlay, const FlightTelemetry& telemetry,
                                           const FrameStamp& frame, double clock_to_unix_s);

 private:
  WireBufferPool pool_;
};

}  // namespace labo::server
