#pragma once
// The WebSocket protocol, client to server: one JSON text message becomes a typed request, or a
// refusal that names what was wrong and what was expected (docs/web.md "WebSocket protocol"). Pure:
// no session, no role, no clock. Who may send what (roles, control, the rate limit) is RemoteLab's.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "server/lab/flight_service.hpp"
#include "server/lab/lab_client.hpp"

namespace labo::server {

// {"type":"command","id":7,"command":"inspect","instrument":"oscilloscope","hold_s":10}
struct CommandRequest {
  std::optional<std::int64_t> id;  // echoed in the ack
  std::string name;                // as sent: "inspect", "emergency_stop", ...
  MissionCommand command;
};
struct HeartbeatRequest {};        // {"type":"heartbeat"}
struct RequestControlRequest {};   // {"type":"request_control"}
struct ReleaseControlRequest {};   // {"type":"release_control"}
struct TakeOverRequest {};         // {"type":"take_over"}
struct SubscribeRequest {          // {"type":"subscribe","video":"h264"|"jpeg","rendition":"auto"|"source"|"low"}
  VideoPath video = VideoPath::Jpeg;
  RenditionChoice rendition = RenditionChoice::Auto;  // H.264 only
};

using ClientRequest = std::variant<CommandRequest, HeartbeatRequest, RequestControlRequest, ReleaseControlRequest,
                                   TakeOverRequest, SubscribeRequest>;

// A message the server refuses: the status of the `error` reply (400) and its text.
struct Refusal {
  int status = 400;
  std::string error;
  bool typed = true;  // the message named its type: it counts against the sender's rate limit
};

using ParsedMessage = std::variant<ClientRequest, Refusal>;

ParsedMessage parse_client_message(std::string_view text);

// An emergency stop acts at once: it is never rate limited and needs no control.
bool is_emergency_stop(const ClientRequest& request);

}  // namespace labo::server
