#pragma once
// The remote lab as the clients see it: who is connected (ClientRegistry), who flies (ControlQueue),
// what a client's message asks (lab_protocol) and whether the client may ask it (roles, control, the
// rate limit), and the fan-out of telemetry, events and video from the FlightService. Thread-safe:
// client sessions call in from their strands, the runtime from its threads, the server's timer from
// the io_context. No lock is held while a message is delivered.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/audit/audit_log.hpp"
#include "server/lab/client_registry.hpp"
#include "server/lab/control_queue.hpp"
#include "server/lab/flight_service.hpp"
#include "server/lab/followed_person.hpp"
#include "server/lab/lab_protocol.hpp"
#include "server/lab/replay_service.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

class RemoteLab final : public FlightEventSink {
 public:
  RemoteLab(FlightService& flight, const ServerSettings& settings, ServerMetrics& metrics, const Clock& clock,
            AuditLog& audit, Logger log);
  ~RemoteLab() override;

  void join(const std::shared_ptr<LabClient>& client);
  void leave(ClientId client);
  void log_disconnect(ClientId client, const std::string& reason);
  void disconnect_all(const std::string& reason);
  // Ends the connections of the sessions `match` accepts (a session ended, a user removed); how many.
  std::size_t disconnect_where(const std::function<bool(const SessionInfo&)>& match, const std::string& reason) {
    return clients_.disconnect_where(match, reason);
  }
  // One text message from a client: commands, heartbeats, control requests. Replies go to the client.
  void on_message(LabClient& client, const std::string& text);
  // Called periodically (telemetry_hz): the control queue's clock and the telemetry broadcast.
  void tick();

  void on_frame(const WireFrame& frame) override;
  void on_access_unit(const WireAccessUnit& unit) override;
  void on_reading_view(std::shared_ptr<const std::string> view) override;
  void on_flight_event(const FlightEvent& event) override;
  bool wants_jpeg() const override { return clients_.watching(VideoPath::Jpeg) > 0; }
  bool wants_access_units() const override {
    return clients_.watching(VideoPath::H264) + clients_.watching(VideoPath::Geometry) > 0;
  }
  bool wants_reading_view() const override { return clients_.size() > 0; }
  bool wants_low_rendition() const override { return clients_.low_rendition_viewers() > 0; }
  bool take_low_keyframe_request() override { return low_keyframe_wanted_.exchange(false); }
  // The H.264 renditions a client needs now (its session's RenditionSwitch::needed()).
  void set_renditions(ClientId client, unsigned renditions);

  // A stop or an emergency stop sent over REST, by the same rules as over the WebSocket (the
  // controller being the user who holds control on one of their connections). `status` is the HTTP
  // status: 200 when the flight software answered (accepted or not), 403 when the role may not.
  struct RestCommandResult {
    int status = 200;
    CommandVerdict verdict;
  };
  RestCommandResult stop_from_rest(const SessionInfo& session, MissionCommandKind kind);

  // A teacher or an admin ends the turn of `user`, the student holding control, with `reason`; the
  // student's notice names who and why. `status`: 200, or 409 when `user` does not hold control or
  // is not a student (a teacher's control is taken over, not ended).
  struct EndTurnResult {
    int status = 200;
    std::string message;
  };
  EndTurnResult end_turn(const SessionInfo& by, const std::string& user, const std::string& reason);

  // JSON for REST: the queue and the connected clients.
  std::string control_state_json() const;
  std::size_t client_count() const { return clients_.size(); }

  FlightService& flight() { return flight_; }
  FollowedPerson& followed_person() { return followed_; }
  ReplayService& replays() { return replays_; }

 private:
  void execute(LabClient& client, const CommandRequest& request);
  void execute(LabClient& client, const HeartbeatRequest& request);
  void execute(LabClient& client, const RequestControlRequest& request);
  void execute(LabClient& client, const ReleaseControlRequest& request);
  void execute(LabClient& client, const TakeOverRequest& request);
  void execute(LabClient& client, const SubscribeRequest& request);
  bool has_control(ClientId client) const;
  // Whether `session` may cut the motors: a teacher, an admin, or the one holding control.
  bool may_cut_motors(const SessionInfo& session, bool controlling) const;
  // A stop or emergency stop that passed the checks: to the drone, audited, announced to everyone.
  CommandVerdict stop(const SessionInfo& session, MissionCommandKind kind, const std::string& via);
  void audit_command(const SessionInfo& session, const std::string& command, const CommandVerdict& verdict);
  // A change of the control queue (its notices), made by `change` under control_mutex_; the notices
  // and everyone's view of the new state are sent once it is released.
  template <typename Change>
  void change_control(Change change);
  // Everyone's control message, built under control_mutex_.
  void add_control_views(std::vector<std::pair<ClientId, ClientRegistry::Message>>& out);

  FlightService& flight_;
  ServerSettings settings_;
  ServerMetrics& metrics_;
  const Clock& clock_;
  AuditLog& audit_;
  Logger log_;
  ClientRegistry clients_;
  mutable std::mutex control_mutex_;  // control_, control_seq_, last_control_broadcast_s_
  ControlQueue control_;
  std::uint64_t control_seq_ = 0;
  double last_control_broadcast_s_ = -1;
  std::uint64_t slam_map_sent_ = 0;  // tick()'s only: the revision of the SLAM map last sent
  std::atomic<bool> low_keyframe_wanted_{false};
  FollowedPerson followed_;
  ReplayService replays_;  // after clients_: its player stops before the clients go
};

}  // namespace labo::server
