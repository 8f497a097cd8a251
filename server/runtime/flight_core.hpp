#pragma once
// What the real-time runtime needs from the deterministic flight software: control's FlightStack,
// seen through FlightStackCore (the adapter), or a scripted double in tests. Single-threaded: the
// runtime calls every method from its one flight thread.
#include <vector>

#include "drone/drone_link.hpp"
#include "server/lab/flight_service.hpp"
#include "server/video/overlay_model.hpp"

namespace labo::fusion {
struct VisionJob;
struct VisionResults;
}  // namespace labo::fusion

namespace labo::server {

// What the flight software wants sent to the drone after a tick.
struct FlightAction {
  enum class Kind { None, Move, Hover, Takeoff, Land, Emergency };
  Kind kind = Kind::None;
  MoveCommand move;
  std::optional<CameraId> select_camera;
};

struct FlightSnapshot {
  FlightTelemetry telemetry;  // t_unix_s, link state, fps and the timeline are filled by the runtime
  MissionProgress progress;   // the mission's stage and how the last one ended, for the timeline
  OverlayModel overlay;       // in the pixels of the last frame given to on_video
  std::vector<FlightEvent> events;  // stage changes and errors since the previous status()
};

class FlightCore {
 public:
  virtual ~FlightCore() = default;
  virtual void on_navdata(const NavdataSample& sample) = 0;
  virtual void on_video(const VideoFrame& frame) = 0;
  // A frame's vision in steps, so that the runtime runs it on its worker (VisionWorker): prepare
  // here, fusion::run_vision_job() there, apply back here. False: the frame needs no worker (a core without
  // that split handles the frame inline, as on_video).
  virtual bool prepare_vision(const VideoFrame& frame, fusion::VisionJob&) {
    on_video(frame);
    return false;
  }
  virtual void apply_vision(const fusion::VisionResults&) {}
  virtual void on_link_state(LinkState state, Seconds t) = 0;
  virtual FlightAction tick(Seconds t) = 0;
  virtual CommandVerdict request(const MissionCommand& command, Seconds t) = 0;
  virtual FlightSnapshot status() = 0;
  virtual std::vector<InstrumentSummary> instruments() const = 0;
  // An instrument placed in the lab while the server runs (FlightService::add_instrument).
  virtual CommandVerdict add_instrument(const lab::InstrumentSpec& spec) {
    return {false, "instrument '" + spec.id + "': this flight software cannot add instruments"};
  }
  virtual CommandVerdict remove_instrument(const std::string& id) {
    return {false, "instrument '" + id + "': this flight software cannot remove instruments"};
  }
  // FlightService::set_down_on_platform, on the flight thread.
  virtual CommandVerdict set_down_on_platform() { return {false, "this flight software cannot be told where the drone is"}; }
};

}  // namespace labo::server
