#pragma once
// The WebSocket protocol, server to client: each message serialised once into a string that every
// client it goes to shares (docs/web.md "WebSocket protocol").
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/auth/session_store.hpp"
#include "server/lab/control_queue.hpp"
#include "server/lab/flight_service.hpp"
#include "server/lab/lab_client.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

using Message = std::shared_ptr<const std::string>;

// {"type":"hello","client","user","role","instruments","lab","heartbeat_timeout_s","time_limit_s"}; "lab":
// the room outline (null when unknown).
Message hello_message(ClientId client, const SessionInfo& session, const std::vector<InstrumentSummary>& instruments,
                      const LabOutline& lab, const ControlRules& rules);
// {"type":"error","status":..,"error":..}
Message error_message(int status, const std::string& error);
// {"type":"ack","id","command","accepted","reason"}; `id` null when the command had none.
Message ack_message(std::optional<std::int64_t> id, const std::string& command, const CommandVerdict& verdict);
// {"type":"notice","kind":"granted|warning|ended",...}; an ended turn has its "reason", and "by" when a
// teacher or an admin ended it.
Message notice_message(const ControlNotice& notice);
Message telemetry_message(const FlightTelemetry& telemetry);
// {"type":"slam_map","revision","map_id","cell_m","points":[[x,y],...]}: the SLAM map from above, world
// m to the centimetre.
Message slam_map_message(const fusion::SlamPointsXy& points);
Message flight_event_message(const FlightEvent& event);
// {"type":"event","kind":"emergency"|"stop","user","message"}: who cut the motors, or who stopped.
Message emergency_event_message(const std::string& user);
Message stop_event_message(const std::string& user);
// {"type":"subscribed","video":"h264|jpeg"}: the path this client's video now takes.
Message subscribed_message(VideoPath video);
// {"type":"rendition","rendition":"source|low","choice":"auto|source|low","reason","throughput_kbps","lag_s"}:
// the H.264 rendition this client is moving to (it switches at that rendition's next IDR), why, and
// what its link carried over the last seconds.
Message rendition_message(Rendition rendition, RenditionChoice choice, const std::string& reason, double throughput_kbps,
                          double lag_s);

// The control state as one client sees it: who controls, the queue, and where this client stands.
struct ClientControlView {
  ClientId client = 0;
  bool controlling = false;
  std::optional<std::size_t> position;  // 1-based place in the queue
};
// {"type":"control","seq","controller","remaining_s","held_s","queue","spectators","you"}, each queued
// participant with the seconds it has waited ("waited_s"). `seq` grows with
// every state published: states may reach a client out of order (they are sent after the lab's lock
// is released), and the page keeps the newest.
Message control_message(const ControlSnapshot& snapshot, std::size_t spectators, std::uint64_t seq,
                        const ClientControlView& you);
// For REST: the same without "type", "seq" and "you", with every connected client.
std::string control_summary_json(const ControlSnapshot& snapshot, const std::vector<Participant>& clients);

}  // namespace labo::server
