#include "server/lab/lab_protocol.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

namespace labo::server {

using nlohmann::json;

namespace {

constexpr std::string_view kTypes = "command, heartbeat, request_control, release_control, take_over, subscribe";
constexpr std::string_view kCommands =
    "takeoff, inspect, find_teacher, stop_face_follow, return_home, land, stop, emergency_stop, select_camera, jog";
constexpr double kMaxHoldS = 600;
// A jog is a small step: the page sends one per key press, the autopilot flies it at its own speed.
constexpr double kMaxJogM = 0.5;
constexpr double kMaxJogYawDeg = 45;
constexpr double kPi = 3.14159265358979323846;

Refusal refuse(std::string error) { return {400, std::move(error), true}; }
Refusal untyped(std::string error) { return {400, std::move(error), false}; }

ParsedMessage parse_jog(const json& msg, CommandRequest r) {
  if (msg.contains("instrument") || msg.contains("hold_s")) return refuse("'instrument' and 'hold_s' belong to inspect only");
  double* const steps[] = {&r.command.dx_m, &r.command.dy_m, &r.command.dz_m};
  const char* const names[] = {"dx_m", "dy_m", "dz_m"};
  for (int i = 0; i < 3; ++i) {
    if (!msg.contains(names[i])) continue;
    const json& v = msg[names[i]];
    if (!v.is_number() || std::abs(v.get<double>()) > kMaxJogM)
      return refuse(std::string("'") + names[i] + "' must be a number in [-0.5, 0.5] m");
    *steps[i] = v.get<double>();
  }
  if (msg.contains("dyaw_deg")) {
    const json& v = msg["dyaw_deg"];
    if (!v.is_number() || std::abs(v.get<double>()) > kMaxJogYawDeg) return refuse("'dyaw_deg' must be a number in [-45, 45] degrees");
    r.command.dyaw_rad = v.get<double>() * kPi / 180;
  }
  const MissionCommand& c = r.command;
  if (c.dx_m == 0 && c.dy_m == 0 && c.dz_m == 0 && c.dyaw_rad == 0)
    return refuse("jog needs a step: 'dx_m', 'dy_m', 'dz_m' (metres) or 'dyaw_deg'");
  return ClientRequest{std::move(r)};
}

// {"type":"command","command":"select_camera","camera":"front|bottom"}
ParsedMessage parse_camera(const json& msg, CommandRequest r) {
  if (msg.contains("instrument") || msg.contains("hold_s")) return refuse("'instrument' and 'hold_s' belong to inspect only");
  const json* camera = msg.contains("camera") ? &msg["camera"] : nullptr;
  const std::string name = camera && camera->is_string() ? camera->get<std::string>() : "";
  if (name != "front" && name != "bottom") return refuse("select_camera needs 'camera' (string: front or bottom)");
  r.command.camera = name == "bottom" ? CameraId::Bottom : CameraId::Front;
  return ClientRequest{std::move(r)};
}

ParsedMessage parse_command(const json& msg) {
  static constexpr std::array<std::string_view, 10> kFields{"type", "id",   "command", "instrument", "hold_s",
                                                           "camera", "dx_m", "dy_m",    "dz_m",       "dyaw_deg"};
  for (const auto& [key, value] : msg.items())
    if (std::find(kFields.begin(), kFields.end(), key) == kFields.end())
      return refuse("unknown field '" + key + "' in a command");
  CommandRequest r;
  if (msg.contains("id")) {
    if (!msg["id"].is_number_integer()) return refuse("'id' must be an integer");
    r.id = msg["id"].get<std::int64_t>();
  }
  if (!msg.contains("command") || !msg["command"].is_string()) return refuse("'command' (string) is required");
  r.name = msg["command"].get<std::string>();
  const auto kind = parse_mission_command(r.name);
  if (!kind) return refuse("unknown command '" + r.name + "' (expected " + std::string(kCommands) + ")");
  r.command = MissionCommand{*kind, "", 10};
  const bool jog_fields = msg.contains("dx_m") || msg.contains("dy_m") || msg.contains("dz_m") || msg.contains("dyaw_deg");
  if (*kind != MissionCommandKind::Jog && jog_fields) return refuse("'dx_m', 'dy_m', 'dz_m' and 'dyaw_deg' belong to jog only");
  if (*kind == MissionCommandKind::SelectCamera) return parse_camera(msg, std::move(r));
  if (msg.contains("camera")) return refuse("'camera' belongs to select_camera only");
  if (*kind == MissionCommandKind::Jog) return parse_jog(msg, std::move(r));
  if (*kind != MissionCommandKind::Inspect) {
    if (msg.contains("instrument") || msg.contains("hold_s")) return refuse("'instrument' and 'hold_s' belong to inspect only");
    return ClientRequest{std::move(r)};
  }
  if (!msg.contains("instrument") || !msg["instrument"].is_string())
    return refuse("inspect needs 'instrument' (string, an instrument id)");
  r.command.instrument = msg["instrument"].get<std::string>();
  if (msg.contains("hold_s")) {
    const json& hold = msg["hold_s"];
    if (!hold.is_number() || hold.get<double>() <= 0 || hold.get<double>() > kMaxHoldS)
      return refuse("'hold_s' must be a number in (0, 600] seconds");
    r.command.hold_s = hold.get<double>();
  }
  return ClientRequest{std::move(r)};
}

ParsedMessage parse_subscribe(const json& msg) {
  for (const auto& [key, value] : msg.items())
    if (key != "type" && key != "video" && key != "rendition")
      return refuse("unknown field '" + key + "' in subscribe (expected 'video' and optionally 'rendition')");
  if (!msg.contains("video") || !msg["video"].is_string()) return refuse("subscribe needs 'video' (string: h264, jpeg, geometry or none)");
  const std::string name = msg["video"].get<std::string>();
  const auto path = parse_video_path(name);
  if (!path) return refuse("unknown video path '" + name + "' (expected h264, jpeg, geometry or none)");
  SubscribeRequest r{*path, RenditionChoice::Auto};
  if (!msg.contains("rendition")) return ClientRequest{r};
  if (*path != VideoPath::H264) return refuse("'rendition' belongs to the h264 path only");
  const json& rendition = msg["rendition"];
  const auto choice = rendition.is_string() ? parse_rendition_choice(rendition.get<std::string>()) : std::nullopt;
  if (!choice) return refuse("'rendition' must be auto, source or low");
  r.rendition = *choice;
  return ClientRequest{r};
}

// The messages that carry nothing but their type.
struct BareMessage {
  std::string_view type;
  ClientRequest request;
};
const std::array<BareMessage, 4> kBareMessages{{
    {"heartbeat", HeartbeatRequest{}},
    {"request_control", RequestControlRequest{}},
    {"release_control", ReleaseControlRequest{}},
    {"take_over", TakeOverRequest{}},
}};

}  // namespace

ParsedMessage parse_client_message(std::string_view text) {
  const json msg = json::parse(text, nullptr, false);
  if (msg.is_discarded()) return untyped("malformed JSON");
  if (!msg.is_object()) return untyped("expected a JSON object");
  if (!msg.contains("type") || !msg["type"].is_string()) return untyped("'type' (string) is required");
  const std::string type = msg["type"].get<std::string>();
  if (type == "command") return parse_command(msg);
  if (type == "subscribe") return parse_subscribe(msg);
  for (const BareMessage& m : kBareMessages) {
    if (m.type != type) continue;
    if (msg.size() != 1) return refuse("'" + type + "' takes no other field");
    return m.request;
  }
  return refuse("unknown message type '" + type + "' (expected " + std::string(kTypes) + ")");
}

bool is_emergency_stop(const ClientRequest& request) {
  const auto* c = std::get_if<CommandRequest>(&request);
  return c && c->command.kind == MissionCommandKind::EmergencyStop;
}

}  // namespace labo::server
