#pragma once
// The shared state of the remote lab: connected clients, the control queue, the WebSocket command
// protocol, and the fan-out of telemetry, events and video from the FlightService. Thread-safe: client
// sessions call in from their strands, the runtime from its threads, the server's timer from the
// io_context. Frames and events are serialized once and shared by every client.
#include <map>
#include <vector>
#include <memory>
#include <mutex>
#include <string>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/auth/session_store.hpp"
#include "server/auth/token_bucket.hpp"
#include "server/lab/control_queue.hpp"
#include "server/lab/flight_service.hpp"
#include "server/lab/lab_client.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo {

class RemoteLab final : public FlightEventSink {
 public:
  RemoteLab(FlightService& flight, const ServerSettings& settings, ServerMetrics& metrics, const Clock& clock,
            Logger log);
  ~RemoteLab() override;

  void join(const std::shared_ptr<LabClient>& client);
  void leave(ClientId client);
  void log_disconnect(ClientId client, const std::string& reason);
  void disconnect_all(const std::string& reason);
  // One text message from a client: commands, heartbeats, control requests. Replies go to the client.
  void on_message(LabClient& client, const std::string& text);
  // Called periodically (telemetry_hz): the control queue's clock and the telemetry broadcast.
  void tick();

  void on_frame(const WireFrame& frame) override;
  void on_flight_event(const FlightEvent& event) override;

  // JSON for REST: the queue and the connected clients.
  std::string control_state_json() const;
  std::size_t client_count() const;
  // {"type":"error","status":..,"error":..}
  static std::shared_ptr<const std::string> error_json(int status, const std::string& message);

  FlightService& flight() { return flight_; }

 private:
  struct Client {
    std::weak_ptr<LabClient> link;
    Participant who;
    TokenBucket bucket;
  };
  void handle_command(LabClient& client, const std::string& text);
  void deliver(const std::vector<ControlNotice>& notices);       // with mutex_ held
  void broadcast_control_state();                                 // with mutex_ held
  void broadcast(const std::shared_ptr<const std::string>& json);  // takes mutex_
  std::string control_json_for(ClientId client) const;            // with mutex_ held
  // Holds mutex_; the sessions kept alive while it was held are released after it is unlocked.
  class Locked;
  // A weak link locked under mutex_ may be a session's last owner (it closed meanwhile on the server's
  // thread): destroyed there, its destructor leaves the lab, which takes mutex_ again, a deadlock
  // (test "web: a WebSocket needs a session, and commands need control except the emergency
  // stop"). deliver() and broadcast_control_state() park the links they locked here, and Locked
  // releases them after unlocking.
  std::vector<std::shared_ptr<LabClient>> release_after_unlock_;

  FlightService& flight_;
  ServerSettings settings_;
  ServerMetrics& metrics_;
  const Clock& clock_;
  Logger log_;
  mutable std::mutex mutex_;
  std::map<ClientId, Client> clients_;
  ControlQueue control_;
  double last_control_broadcast_s_ = -1;
};

}  // namespace labo
