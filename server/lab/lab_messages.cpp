#include "server/lab/lab_messages.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace labo::server {

using nlohmann::json;

namespace {

Message shared(const json& j) { return std::make_shared<const std::string>(j.dump()); }

json pose_json(const PoseXyzYaw& p) { return {{"x", p.x_m}, {"y", p.y_m}, {"z", p.z_m}, {"yaw", p.yaw_rad}}; }

json footprint_json(const LabFootprint& f) {
  return {{"id", f.id}, {"min", {f.min_x_m, f.min_y_m}}, {"max", {f.max_x_m, f.max_y_m}}};
}

json outline_json(const LabOutline& lab) {
  if (!lab.known) return nullptr;
  json benches = json::array();
  for (const LabFootprint& b : lab.benches) benches.push_back(footprint_json(b));
  return {{"room", footprint_json(lab.room)},
          {"benches", std::move(benches)},
          {"platform", footprint_json(lab.platform)},
          {"base", {{"x", lab.base_x_m}, {"y", lab.base_y_m}, {"yaw", lab.base_yaw_rad}}}};
}

double centimetres(float v) { return std::round(static_cast<double>(v) * 100.0) / 100.0; }

json optional_time(const std::optional<Seconds>& t) { return t ? json(*t) : json(nullptr); }

json timeline_json(const MissionTimeline& m) {
  if (m.mission.empty()) return nullptr;
  json stages = json::array();
  for (const TimelineStage& s : m.stages)
    stages.push_back({{"index", s.index}, {"name", s.name}, {"started", s.started}, {"ended", optional_time(s.ended)},
                      {"waiting_for", s.waiting_for}});
  return {{"mission", m.mission},   {"stage_count", m.stage_count}, {"started", m.started},
          {"ended", optional_time(m.ended)}, {"result", m.result}, {"succeeded", m.succeeded},
          {"dropped", m.dropped},   {"stages", std::move(stages)}};
}

json participant_json(const Participant& p) { return {{"user", p.user}, {"role", to_string(p.role)}, {"client", p.client}}; }

json control_json(const ControlSnapshot& s, std::size_t spectators) {
  json queue = json::array();
  for (std::size_t i = 0; i < s.queue.size(); ++i) {
    json entry = participant_json(s.queue[i]);
    entry["waited_s"] = i < s.waited_s.size() ? s.waited_s[i] : 0.0;
    queue.push_back(std::move(entry));
  }
  return {{"controller", s.controller ? participant_json(*s.controller) : json(nullptr)},
          {"remaining_s", s.remaining_s},
          {"held_s", s.held_s},
          {"queue", queue},
          {"spectators", spectators}};
}

}  // namespace

Message hello_message(ClientId client, const SessionInfo& session, const std::vector<InstrumentSummary>& instruments,
                      const LabOutline& lab, const ControlRules& rules) {
  json list = json::array();
  for (const InstrumentSummary& i : instruments)
    list.push_back({{"id", i.id}, {"name", i.name}, {"width_m", i.width_m}, {"height_m", i.height_m}, {"x", i.x_m}, {"y", i.y_m},
                    {"facing_rad", i.facing_rad}});
  return shared({{"type", "hello"},
                 {"client", client},
                 {"user", session.user},
                 {"role", to_string(session.role)},
                 {"instruments", list},
                 {"lab", outline_json(lab)},
                 {"heartbeat_timeout_s", rules.heartbeat_timeout_s},
                 {"time_limit_s", rules.time_limit_s}});
}

Message error_message(int status, const std::string& error) {
  return shared({{"type", "error"}, {"status", status}, {"error", error}});
}

Message ack_message(std::optional<std::int64_t> id, const std::string& command, const CommandVerdict& verdict) {
  return shared({{"type", "ack"},
                 {"id", id ? json(*id) : json(nullptr)},
                 {"command", command},
                 {"accepted", verdict.accepted},
                 {"reason", verdict.reason}});
}

Message notice_message(const ControlNotice& n) {
  json j{{"type", "notice"}};
  switch (n.kind) {
    case ControlNotice::Kind::Granted: j["kind"] = "granted"; j["remaining_s"] = n.remaining_s; break;
    case ControlNotice::Kind::Warning: j["kind"] = "warning"; j["remaining_s"] = n.remaining_s; break;
    case ControlNotice::Kind::Ended:
      j["kind"] = "ended";
      j["reason"] = n.reason;
      if (!n.by.empty()) j["by"] = n.by;
      break;
  }
  return shared(j);
}

Message telemetry_message(const FlightTelemetry& t) {
  json j{{"type", "telemetry"},
         {"t", t.t_unix_s},
         {"mission", t.mission},
         {"stage", t.stage},
         {"pose", pose_json(t.pose)},
         {"source", to_string(t.source)},
         {"source_colour", colour_of(t.source)},
         {"source_quality", t.source_quality},
         {"unobserved_flight_s", t.unobserved_flight_s},
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
  j["timeline"] = timeline_json(t.timeline);
  return shared(j);
}

Message slam_map_message(const fusion::SlamPointsXy& p) {
  json points = json::array();
  for (const Eigen::Vector2f& xy : p.xy_world) points.push_back({centimetres(xy.x()), centimetres(xy.y())});
  return shared({{"type", "slam_map"}, {"revision", p.revision}, {"map_id", p.map_id}, {"cell_m", p.cell_m}, {"points", std::move(points)}});
}

Message flight_event_message(const FlightEvent& e) {
  return shared({{"type", "event"}, {"kind", e.kind}, {"mission", e.mission}, {"stage", e.stage}, {"message", e.message}});
}

Message emergency_event_message(const std::string& user) {
  return shared({{"type", "event"}, {"kind", "emergency"}, {"user", user}, {"message", "emergency stop by " + user + ": motors cut"}});
}

Message stop_event_message(const std::string& user) {
  return shared({{"type", "event"}, {"kind", "stop"}, {"user", user}, {"message", "stop by " + user + ": hovering, then landing"}});
}

Message subscribed_message(VideoPath video) { return shared({{"type", "subscribed"}, {"video", to_string(video)}}); }

Message rendition_message(Rendition rendition, RenditionChoice choice, const std::string& reason, double throughput_kbps,
                          double lag_s) {
  return shared({{"type", "rendition"},
                 {"rendition", to_string(rendition)},
                 {"choice", to_string(choice)},
                 {"reason", reason},
                 {"throughput_kbps", std::round(throughput_kbps)},
                 {"lag_s", std::round(lag_s * 100) / 100}});
}

Message control_message(const ControlSnapshot& snapshot, std::size_t spectators, std::uint64_t seq,
                        const ClientControlView& you) {
  json j = control_json(snapshot, spectators);
  j["type"] = "control";
  j["seq"] = seq;
  j["you"] = {{"client", you.client}, {"controlling", you.controlling}, {"position", you.position ? json(*you.position) : json(nullptr)}};
  return shared(j);
}

std::string control_summary_json(const ControlSnapshot& snapshot, const std::vector<Participant>& clients) {
  json j = control_json(snapshot, clients.size());
  json list = json::array();
  for (const Participant& p : clients) list.push_back(participant_json(p));
  j["clients"] = std::move(list);
  return j.dump();
}

}  // namespace labo::server
