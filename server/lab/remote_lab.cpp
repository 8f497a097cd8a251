#include "server/lab/remote_lab.hpp"

#include <chrono>
#include <nlohmann/json.hpp>
#include <set>

#include "server/auth/permissions.hpp"

namespace labo {

class RemoteLab::Locked {
 public:
  explicit Locked(RemoteLab& lab) : lab_(lab), lock_(lab.mutex_) {}
  Locked(const Locked&) = delete;
  Locked& operator=(const Locked&) = delete;
  ~Locked() {
    std::vector<std::shared_ptr<LabClient>> release;
    release.swap(lab_.release_after_unlock_);
    lock_.unlock();
  }  // `release` goes here, unlocked: a session it held last leaves the lab without a deadlock

 private:
  RemoteLab& lab_;
  std::unique_lock<std::mutex> lock_;
};

using nlohmann::json;

namespace {

std::shared_ptr<const std::string> shared_json(const json& j) { return std::make_shared<const std::string>(j.dump()); }

json pose_json(const PoseXyzYaw& p) { return {{"x", p.x_m}, {"y", p.y_m}, {"z", p.z_m}, {"yaw", p.yaw_rad}}; }

json telemetry_json(const FlightTelemetry& t) {
  json j{{"type", "telemetry"},
         {"t", t.t_unix_s},
         {"mission", t.mission},
         {"stage", t.stage},
         {"pose", pose_json(t.pose)},
         {"source", to_string(t.source)},
         {"source_colour", colour_of(t.source)},
         {"source_quality", t.source_quality},
         {"battery_percent", t.battery_percent},
         {"altitude_m", t.altitude_m},
         {"link_quality", t.link_quality},
         {"link_state", t.link_state},
         {"flying", t.flying},
         {"slam_state", t.slam_state},
         {"video_fps", t.video_fps}};
  j["desired"] = t.desired ? pose_json(*t.desired) : json(nullptr);
  j["ground_truth"] = t.ground_truth ? pose_json(*t.ground_truth) : json(nullptr);
  j["teacher"] = t.teacher_xy ? json{t.teacher_xy->first, t.teacher_xy->second} : json(nullptr);
  json points = json::array();
  for (const auto& [x, y] : t.slam_points_xy) points.push_back({x, y});
  j["slam_points"] = std::move(points);
  return j;
}

json participant_json(const Participant& p) { return {{"user", p.user}, {"role", to_string(p.role)}, {"client", p.client}}; }

}  // namespace

RemoteLab::RemoteLab(FlightService& flight, const ServerSettings& settings, ServerMetrics& metrics, const Clock& clock,
                     Logger log)
    : flight_(flight), settings_(settings), metrics_(metrics), clock_(clock), log_(std::move(log)), control_(settings.control) {
  flight_.set_sink(this);
}

RemoteLab::~RemoteLab() { flight_.set_sink(nullptr); }

std::shared_ptr<const std::string> RemoteLab::error_json(int status, const std::string& message) {
  return shared_json({{"type", "error"}, {"status", status}, {"error", message}});
}

void RemoteLab::join(const std::shared_ptr<LabClient>& client) {
  const SessionInfo& s = client->session();
  json instruments = json::array();
  for (const InstrumentSummary& i : flight_.instruments())
    instruments.push_back({{"id", i.id}, {"name", i.name}, {"width_m", i.width_m}, {"height_m", i.height_m}, {"x", i.x_m}, {"y", i.y_m}});
  client->send_event(shared_json({{"type", "hello"},
                                  {"client", client->id()},
                                  {"user", s.user},
                                  {"role", to_string(s.role)},
                                  {"instruments", instruments},
                                  {"heartbeat_timeout_s", settings_.control.heartbeat_timeout_s},
                                  {"time_limit_s", settings_.control.time_limit_s}}));
  Locked lock(*this);
  clients_.emplace(client->id(), Client{client, Participant{client->id(), s.user, s.role},
                                        TokenBucket(settings_.clients.commands_per_s, settings_.clients.command_burst)});
  log_.info(clock_.now(), "client joined").kv("client", client->id()).kv("user", s.user).kv("role", to_string(s.role));
  broadcast_control_state();
}

void RemoteLab::leave(ClientId client) {
  Locked lock(*this);
  clients_.erase(client);
  deliver(control_.leave(client, clock_.now()));
  broadcast_control_state();
}

void RemoteLab::log_disconnect(ClientId client, const std::string& reason) {
  log_.info(clock_.now(), "client disconnected").kv("client", client).kv("reason", reason);
}

void RemoteLab::disconnect_all(const std::string& reason) {
  std::vector<std::shared_ptr<LabClient>> targets;
  {
    Locked lock(*this);
    for (const auto& [id, c] : clients_)
      if (auto link = c.link.lock()) targets.push_back(std::move(link));
  }
  for (const auto& t : targets) t->disconnect(reason);
}

void RemoteLab::on_message(LabClient& client, const std::string& text) {
  const auto reply_error = [&](int status, const std::string& message) {
    client.send_event(error_json(status, message));
  };
  json msg = json::parse(text, nullptr, false);
  if (msg.is_discarded()) return reply_error(400, "malformed JSON");
  if (!msg.is_object()) return reply_error(400, "expected a JSON object");
  if (!msg.contains("type") || !msg["type"].is_string()) return reply_error(400, "'type' (string) is required");
  const std::string type = msg["type"];
  const bool emergency = type == "command" && msg.value("command", json()) == "emergency_stop";
  const double now = clock_.now();
  {
    Locked lock(*this);
    auto it = clients_.find(client.id());
    if (it == clients_.end()) return;
    // Emergency stop is never rate limited: it must act at once, whatever came before.
    if (!emergency && !it->second.bucket.take(now)) {
      metrics_.rate_limited++;
      return reply_error(429, "too many messages: at most " + std::to_string(settings_.clients.commands_per_s) +
                                  " per second (burst " + std::to_string(settings_.clients.command_burst) + ")");
    }
  }
  if (type == "command") return handle_command(client, text);
  if (msg.size() != 1) return reply_error(400, "'" + type + "' takes no other field");
  const Participant who{client.id(), client.session().user, client.session().role};
  Locked lock(*this);
  if (type == "heartbeat") {
    control_.heartbeat(client.id(), now);
  } else if (type == "request_control") {
    deliver(control_.request(who, now));
    broadcast_control_state();
  } else if (type == "release_control") {
    deliver(control_.release(client.id(), now));
    broadcast_control_state();
  } else if (type == "take_over") {
    if (!role_may(who.role, Permission::TakeOver)) return reply_error(403, "only a teacher or an admin may take over");
    deliver(control_.take_over(who, now));
    broadcast_control_state();
  } else {
    reply_error(400, "unknown message type '" + type +
                         "' (expected command, heartbeat, request_control, release_control, take_over)");
  }
}

void RemoteLab::handle_command(LabClient& client, const std::string& text) {
  const json msg = json::parse(text);
  const auto reply_error = [&](int status, const std::string& message) {
    client.send_event(error_json(status, message));
  };
  static const std::set<std::string> kFields{"type", "id", "command", "instrument", "hold_s"};
  for (const auto& [key, value] : msg.items())
    if (!kFields.contains(key)) return reply_error(400, "unknown field '" + key + "' in a command");
  if (msg.contains("id") && !msg["id"].is_number_integer()) return reply_error(400, "'id' must be an integer");
  if (!msg.contains("command") || !msg["command"].is_string()) return reply_error(400, "'command' (string) is required");
  const json id = msg.value("id", json(nullptr));
  const std::string name = msg["command"];
  const auto kind = parse_mission_command(name);
  const auto ack = [&](bool accepted, const std::string& reason) {
    (accepted ? metrics_.commands_accepted : metrics_.commands_rejected)++;
    client.send_event(shared_json({{"type", "ack"}, {"id", id}, {"command", name}, {"accepted", accepted}, {"reason", reason}}));
  };
  if (!kind)
    return reply_error(400, "unknown command '" + name +
                                "' (expected takeoff, inspect, find_teacher, stop_face_follow, return_home, land, emergency_stop)");
  MissionCommand command{*kind, "", 10};
  if (*kind == MissionCommandKind::Inspect) {
    if (!msg.contains("instrument") || !msg["instrument"].is_string())
      return reply_error(400, "inspect needs 'instrument' (string, an instrument id)");
    command.instrument = msg["instrument"];
    if (msg.contains("hold_s")) {
      if (!msg["hold_s"].is_number() || msg["hold_s"].get<double>() <= 0 || msg["hold_s"].get<double>() > 600)
        return reply_error(400, "'hold_s' must be a number in (0, 600] seconds");
      command.hold_s = msg["hold_s"];
    }
  } else if (msg.contains("instrument") || msg.contains("hold_s")) {
    return reply_error(400, "'instrument' and 'hold_s' belong to inspect only");
  }
  const Role role = client.session().role;
  const Permission needed = *kind == MissionCommandKind::EmergencyStop ? Permission::EmergencyStop : Permission::RequestControl;
  if (!role_may(role, needed)) return ack(false, "role " + to_string(role) + " may not send " + name);
  if (*kind != MissionCommandKind::EmergencyStop) {
    Locked lock(*this);
    if (!control_.is_controller(client.id()))
      return ack(false, "you do not have control: request it and wait for your turn");
  }
  const CommandVerdict verdict = flight_.request(command);
  log_.info(clock_.now(), "command")
      .kv("user", client.session().user)
      .kv("command", name)
      .kv("accepted", verdict.accepted)
      .kv("reason", verdict.reason);
  ack(verdict.accepted, verdict.reason);
  if (*kind == MissionCommandKind::EmergencyStop && verdict.accepted)
    broadcast(shared_json({{"type", "event"}, {"kind", "emergency"}, {"message", "emergency stop by " + client.session().user}}));
}

void RemoteLab::deliver(const std::vector<ControlNotice>& notices) {
  for (const ControlNotice& n : notices) {
    auto it = clients_.find(n.client);
    if (it == clients_.end()) continue;
    auto link = it->second.link.lock();
    if (!link) continue;
    release_after_unlock_.push_back(link);
    json j{{"type", "notice"}};
    switch (n.kind) {
      case ControlNotice::Kind::Granted: j["kind"] = "granted"; j["remaining_s"] = n.remaining_s; break;
      case ControlNotice::Kind::Warning: j["kind"] = "warning"; j["remaining_s"] = n.remaining_s; break;
      case ControlNotice::Kind::Ended: j["kind"] = "ended"; j["reason"] = n.reason; break;
    }
    link->send_event(shared_json(j));
  }
}

std::string RemoteLab::control_json_for(ClientId client) const {
  const ControlSnapshot s = control_.snapshot(clock_.now());
  json queue = json::array();
  for (const Participant& p : s.queue) queue.push_back(participant_json(p));
  json j{{"type", "control"},
         {"controller", s.controller ? participant_json(*s.controller) : json(nullptr)},
         {"remaining_s", s.remaining_s},
         {"queue", queue},
         {"spectators", clients_.size()}};
  if (client != 0) {
    const auto pos = control_.queue_position(client);
    j["you"] = {{"client", client}, {"controlling", control_.is_controller(client)}, {"position", pos ? json(*pos) : json(nullptr)}};
  }
  return j.dump();
}

void RemoteLab::broadcast_control_state() {
  metrics_.queue_length = static_cast<std::int64_t>(control_.snapshot(clock_.now()).queue.size());
  for (const auto& [id, c] : clients_)
    if (auto link = c.link.lock()) {
      link->send_event(std::make_shared<const std::string>(control_json_for(id)));
      release_after_unlock_.push_back(std::move(link));
    }
}

void RemoteLab::broadcast(const std::shared_ptr<const std::string>& json_text) {
  std::vector<std::shared_ptr<LabClient>> targets;
  {
    Locked lock(*this);
    for (const auto& [id, c] : clients_)
      if (auto link = c.link.lock()) targets.push_back(std::move(link));
  }
  for (const auto& t : targets) t->send_event(json_text);
}

void RemoteLab::tick() {
  {
    Locked lock(*this);
    const auto notices = control_.tick(clock_.now());
    deliver(notices);
    bool changed = false;
    for (const auto& n : notices) changed = changed || n.kind != ControlNotice::Kind::Warning;
    // The remaining time changes every second: refresh everyone's view of it once a second.
    const double now = clock_.now();
    if (changed || now - last_control_broadcast_s_ >= 1.0) {
      last_control_broadcast_s_ = now;
      broadcast_control_state();
    }
  }
  broadcast(shared_json(telemetry_json(flight_.telemetry())));
}

void RemoteLab::on_frame(const WireFrame& frame) {
  metrics_.frames_published++;
  std::vector<std::shared_ptr<LabClient>> targets;
  {
    Locked lock(*this);
    targets.reserve(clients_.size());
    for (const auto& [id, c] : clients_)
      if (auto link = c.link.lock()) targets.push_back(std::move(link));
  }
  for (const auto& t : targets) t->send_frame(frame.wire);
}

void RemoteLab::on_flight_event(const FlightEvent& event) {
  broadcast(shared_json({{"type", "event"}, {"kind", event.kind}, {"mission", event.mission}, {"stage", event.stage}, {"message", event.message}}));
}

std::string RemoteLab::control_state_json() const {
  std::lock_guard lock(mutex_);
  json j = json::parse(control_json_for(0));
  json clients = json::array();
  for (const auto& [id, c] : clients_) clients.push_back(participant_json(c.who));
  j["clients"] = clients;
  j.erase("type");
  return j.dump();
}

std::size_t RemoteLab::client_count() const {
  std::lock_guard lock(mutex_);
  return clients_.size();
}

}  // namespace labo
