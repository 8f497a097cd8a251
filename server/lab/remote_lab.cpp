#include "server/lab/remote_lab.hpp"

#include "server/auth/permissions.hpp"
#include "server/lab/lab_messages.hpp"

namespace labo::server {

RemoteLab::RemoteLab(FlightService& flight, const ServerSettings& settings, ServerMetrics& metrics, const Clock& clock,
                     AuditLog& audit, Logger log)
    : flight_(flight),
      settings_(settings),
      metrics_(metrics),
      clock_(clock),
      audit_(audit),
      log_(std::move(log)),
      clients_(settings.clients.commands_per_s, settings.clients.command_burst),
      control_(settings.control),
      replays_(clients_, log_.child("replay")) {
  flight_.set_sink(this);
}

RemoteLab::~RemoteLab() { flight_.set_sink(nullptr); }

void RemoteLab::join(const std::shared_ptr<LabClient>& client) {
  const SessionInfo& s = client->session();
  client->send_event(hello_message(client->id(), s, flight_.instruments(), flight_.lab_outline(), settings_.control));
  if (const auto points = flight_.telemetry().slam_points) client->send_event(slam_map_message(*points));
  clients_.join(client);
  log_.info(clock_.now(), "client joined").kv("client", client->id()).kv("user", s.user).kv("role", to_string(s.role));
  change_control([](ControlQueue&, double) { return std::vector<ControlNotice>{}; });
}

void RemoteLab::leave(ClientId client) {
  clients_.leave(client);
  metrics_.low_rendition_viewers = static_cast<std::int64_t>(clients_.low_rendition_viewers());
  change_control([client](ControlQueue& q, double now) { return q.leave(client, now); });
}

void RemoteLab::log_disconnect(ClientId client, const std::string& reason) {
  log_.info(clock_.now(), "client disconnected").kv("client", client).kv("reason", reason);
}

void RemoteLab::disconnect_all(const std::string& reason) { clients_.disconnect_all(reason); }

void RemoteLab::on_message(LabClient& client, const std::string& text) {
  const ParsedMessage parsed = parse_client_message(text);
  const auto* request = std::get_if<ClientRequest>(&parsed);
  const auto* refusal = std::get_if<Refusal>(&parsed);
  // Every message that names its type counts against the rate limit, except an emergency stop: it
  // must act at once, whatever came before.
  if (request ? !is_emergency_stop(*request) : refusal->typed) {
    switch (clients_.admit(client.id(), clock_.now())) {
      case ClientRegistry::Admission::Admitted: break;
      case ClientRegistry::Admission::NotJoined: return;
      case ClientRegistry::Admission::RateLimited:
        metrics_.rate_limited++;
        client.send_event(error_message(429, "too many messages: at most " + std::to_string(settings_.clients.commands_per_s) +
                                                 " per second (burst " + std::to_string(settings_.clients.command_burst) + ")"));
        return;
    }
  }
  if (refusal) return client.send_event(error_message(refusal->status, refusal->error));
  std::visit([&](const auto& r) { execute(client, r); }, *request);
}

void RemoteLab::execute(LabClient& client, const CommandRequest& r) {
  const SessionInfo& session = client.session();
  const auto ack = [&](const CommandVerdict& verdict) {
    (verdict.accepted ? metrics_.commands_accepted : metrics_.commands_rejected)++;
    client.send_event(ack_message(r.id, r.name, verdict));
  };
  const MissionCommandKind kind = r.command.kind;
  const bool controlling = has_control(client.id());
  if (kind == MissionCommandKind::EmergencyStop && !may_cut_motors(session, controlling)) {
    const CommandVerdict refused{false, "only the student holding control, a teacher or an admin may cut the motors; "
                                        "send stop (hover, then land) instead"};
    audit_command(session, r.name, refused);
    client.send_event(error_message(403, refused.reason));
    return ack(refused);
  }
  if (kind == MissionCommandKind::EmergencyStop || kind == MissionCommandKind::Stop) return ack(stop(session, kind, "ws"));
  if (!role_may(session.role, Permission::RequestControl))
    return ack({false, "role " + to_string(session.role) + " may not send " + r.name});
  if (!controlling) {
    const CommandVerdict refused{false, "you do not have control: request it and wait for your turn"};
    audit_command(session, r.name, refused);
    return ack(refused);
  }
  MissionCommand command = r.command;
  if (kind == MissionCommandKind::FindTeacher) command.person = followed_.get();
  const CommandVerdict verdict = flight_.request(command);
  audit_command(session, r.name, verdict);
  ack(verdict);
}

bool RemoteLab::may_cut_motors(const SessionInfo& session, bool controlling) const {
  return controlling || role_may(session.role, Permission::CutMotors);
}

CommandVerdict RemoteLab::stop(const SessionInfo& session, MissionCommandKind kind, const std::string& via) {
  const CommandVerdict verdict = flight_.request(MissionCommand{kind, "", 0});
  audit_command(session, to_string(kind) + (via == "rest" ? " (REST)" : ""), verdict);
  if (verdict.accepted)
    clients_.send(kind == MissionCommandKind::EmergencyStop ? emergency_event_message(session.user) : stop_event_message(session.user));
  return verdict;
}

void RemoteLab::audit_command(const SessionInfo& session, const std::string& command, const CommandVerdict& verdict) {
  log_.info(clock_.now(), "command")
      .kv("user", session.user)
      .kv("command", command)
      .kv("accepted", verdict.accepted)
      .kv("reason", verdict.reason);
  audit_.record({session.user, to_string(session.role), "command", command, verdict.accepted, verdict.reason});
}

RemoteLab::RestCommandResult RemoteLab::stop_from_rest(const SessionInfo& session, MissionCommandKind kind) {
  if (kind == MissionCommandKind::EmergencyStop) {
    bool controlling = false;
    {
      std::lock_guard lock(control_mutex_);
      const ControlSnapshot snapshot = control_.snapshot(clock_.now());
      controlling = snapshot.controller && snapshot.controller->user == session.user;
    }
    if (!may_cut_motors(session, controlling)) {
      const CommandVerdict refused{false, "only the student holding control, a teacher or an admin may cut the motors; "
                                          "POST /api/stop (hover, then land) instead"};
      audit_command(session, "emergency_stop (REST)", refused);
      return {403, refused};
    }
  }
  return {200, stop(session, kind, "rest")};
}

RemoteLab::EndTurnResult RemoteLab::end_turn(const SessionInfo& by, const std::string& user, const std::string& reason) {
  EndTurnResult result;
  change_control([&](ControlQueue& q, double now) {
    const ControlSnapshot s = q.snapshot(now);
    if (!s.controller || s.controller->user != user) {
      result = {409, "'" + user + "' does not hold control" + (s.controller ? " ('" + s.controller->user + "' does)" : std::string())};
      return std::vector<ControlNotice>{};
    }
    if (s.controller->role != Role::Student) {
      result = {409, "'" + user + "' is a " + to_string(s.controller->role) + ": take over instead"};
      return std::vector<ControlNotice>{};
    }
    result.message = "ended the turn of " + user;
    return q.end_turn(by.user, reason, now);
  });
  return result;
}

void RemoteLab::execute(LabClient& client, const HeartbeatRequest&) {
  std::lock_guard lock(control_mutex_);
  control_.heartbeat(client.id(), clock_.now());
}

void RemoteLab::execute(LabClient& client, const RequestControlRequest&) {
  const Participant who{client.id(), client.session().user, client.session().role};
  change_control([&who](ControlQueue& q, double now) { return q.request(who, now); });
}

void RemoteLab::execute(LabClient& client, const ReleaseControlRequest&) {
  change_control([&client](ControlQueue& q, double now) { return q.release(client.id(), now); });
}

void RemoteLab::execute(LabClient& client, const TakeOverRequest&) {
  const Participant who{client.id(), client.session().user, client.session().role};
  const bool allowed = role_may(who.role, Permission::TakeOver);
  audit_.record({who.user, to_string(who.role), "take_over", "", allowed, allowed ? "" : "only a teacher or an admin may take over"});
  if (!allowed) return client.send_event(error_message(403, "only a teacher or an admin may take over"));
  change_control([&who](ControlQueue& q, double now) { return q.take_over(who, now); });
}

void RemoteLab::execute(LabClient& client, const SubscribeRequest& r) {
  client.select_video(r.video, r.rendition);  // first: the client's H.264 queue restarts before units reach it
  clients_.set_video(client.id(), r.video);
  client.send_event(subscribed_message(r.video));
}

bool RemoteLab::has_control(ClientId client) const {
  std::lock_guard lock(control_mutex_);
  return control_.is_controller(client);
}

template <typename Change>
void RemoteLab::change_control(Change change) {
  std::vector<std::pair<ClientId, ClientRegistry::Message>> out;
  {
    std::lock_guard lock(control_mutex_);
    for (const ControlNotice& n : change(control_, clock_.now())) out.emplace_back(n.client, notice_message(n));
    add_control_views(out);
  }
  clients_.send_each(out);
}

void RemoteLab::add_control_views(std::vector<std::pair<ClientId, ClientRegistry::Message>>& out) {
  const double now = clock_.now();
  const ControlSnapshot snapshot = control_.snapshot(now);
  metrics_.queue_length = static_cast<std::int64_t>(snapshot.queue.size());
  last_control_broadcast_s_ = now;
  const std::vector<Participant> everyone = clients_.participants();
  ++control_seq_;
  for (const Participant& p : everyone) {
    const ClientControlView you{p.client, control_.is_controller(p.client), control_.queue_position(p.client)};
    out.emplace_back(p.client, control_message(snapshot, everyone.size(), control_seq_, you));
  }
}

void RemoteLab::tick() {
  std::vector<std::pair<ClientId, ClientRegistry::Message>> out;
  {
    std::lock_guard lock(control_mutex_);
    const double now = clock_.now();
    bool changed = false;
    for (const ControlNotice& n : control_.tick(now)) {
      out.emplace_back(n.client, notice_message(n));
      changed = changed || n.kind != ControlNotice::Kind::Warning;
    }
    // The remaining time changes every second: refresh everyone's view of it once a second.
    if (changed || now - last_control_broadcast_s_ >= 1.0) add_control_views(out);
  }
  clients_.send_each(out);
  const FlightTelemetry telemetry = flight_.telemetry();
  clients_.send(telemetry_message(telemetry));
  // The SLAM map changes about once a second: sent when it does, not with every telemetry message.
  if (telemetry.slam_points && telemetry.slam_points->revision != slam_map_sent_) {
    slam_map_sent_ = telemetry.slam_points->revision;
    clients_.send(slam_map_message(*telemetry.slam_points));
  }
}

void RemoteLab::on_frame(const WireFrame& frame) {
  metrics_.frames_published++;
  clients_.send_frame(frame.wire);
}

void RemoteLab::set_renditions(ClientId client, unsigned renditions) {
  if (clients_.set_renditions(client, renditions)) low_keyframe_wanted_ = true;
  metrics_.low_rendition_viewers = static_cast<std::int64_t>(clients_.low_rendition_viewers());
}

void RemoteLab::on_access_unit(const WireAccessUnit& unit) {
  (unit.rendition == Rendition::Low ? metrics_.low_units_published : metrics_.access_units_published)++;
  clients_.send_access_unit(unit);
}

void RemoteLab::on_reading_view(std::shared_ptr<const std::string> view) {
  metrics_.reading_views_published++;
  clients_.send_reading_view(view);
}

void RemoteLab::on_flight_event(const FlightEvent& event) { clients_.send(flight_event_message(event)); }

std::string RemoteLab::control_state_json() const {
  std::lock_guard lock(control_mutex_);
  return control_summary_json(control_.snapshot(clock_.now()), clients_.participants());
}

}  // namespace labo::server
