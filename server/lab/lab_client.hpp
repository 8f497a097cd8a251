#pragma once
// One connected browser as the RemoteLab sees it. The WebSocket session implements it; tests can
// implement it without sockets. send_* are thread-safe and never block: each client keeps a bounded
// queue of JSON events, a single latest-frame slot for JPEG video, and a bounded queue of H.264
// access units that drops to the next IDR when the client falls behind.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "server/auth/session_store.hpp"
#include "server/lab/control_queue.hpp"
#include "server/lab/flight_service.hpp"

namespace labo::server {

// How a client watches the video: JPEG frames with the overlays drawn in by the server (the
// default), or the drone's own H.264 with the overlays' geometry as data.
// Geometry: the overlays of the H.264 path without its units (the video comes from a media server).
// None: no video over this connection (video and overlays both come from the media server: a Janus
// viewer whose data channel carries the geometry); telemetry and events only.
enum class VideoPath { Jpeg, H264, Geometry, None };
std::string_view to_string(VideoPath path);
std::optional<VideoPath> parse_video_path(std::string_view text);

class LabClient {
 public:
  virtual ~LabClient() = default;
  virtual ClientId id() const = 0;
  virtual const SessionInfo& session() const = 0;
  virtual void send_event(std::shared_ptr<const std::string> json) = 0;
  virtual void send_frame(std::shared_ptr<const std::string> wire) = 0;
  virtual void send_access_unit(const WireAccessUnit& unit) = 0;
  // The instrument reading view: a one-message slot, a newer view replaces the one waiting.
  virtual void send_reading_view(std::shared_ptr<const std::string> view) = 0;
  // A frame of a recording played back (RecordingPlayer, "LDP1"): a one-frame slot of its own, so
  // the live video and the replay do not overwrite each other.
  virtual void send_replay_frame(std::shared_ptr<const std::string> wire) = 0;
  // The path the client chose: H.264 starts at the next IDR, with the rendition it chose (auto: the
  // one its link carries).
  virtual void select_video(VideoPath path, RenditionChoice rendition) = 0;
  virtual void disconnect(const std::string& reason) = 0;
};

}  // namespace labo::server
