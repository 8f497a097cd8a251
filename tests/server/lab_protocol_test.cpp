#include <catch2/catch.hpp>

#include "server/lab/lab_protocol.hpp"

using namespace labo;
using namespace labo::server;

namespace {

// The refusal's "status error" text, or "accepted".
std::string verdict_of(const std::string& text) {
  const ParsedMessage parsed = parse_client_message(text);
  if (const auto* r = std::get_if<Refusal>(&parsed)) return std::to_string(r->status) + " " + r->error;
  return "accepted";
}

template <typename T>
const T& request_of(const ParsedMessage& parsed) {
  REQUIRE(std::holds_alternative<ClientRequest>(parsed));
  const auto& request = std::get<ClientRequest>(parsed);
  REQUIRE(std::holds_alternative<T>(request));
  return std::get<T>(request);
}

}  // namespace

TEST_CASE("lab: protocol: each message type becomes its typed request") {
  const ParsedMessage inspect =
      parse_client_message(R"({"type":"command","id":7,"command":"inspect","instrument":"oscilloscope","hold_s":12.5})");
  const auto& c = request_of<CommandRequest>(inspect);
  CHECK(c.id == 7);
  CHECK(c.name == "inspect");
  CHECK(c.command.kind == MissionCommandKind::Inspect);
  CHECK(c.command.instrument == "oscilloscope");
  CHECK(c.command.hold_s == 12.5);

  const ParsedMessage land = parse_client_message(R"({"type":"command","command":"land"})");
  CHECK_FALSE(request_of<CommandRequest>(land).id);
  CHECK(request_of<CommandRequest>(land).command.kind == MissionCommandKind::Land);
  CHECK(request_of<CommandRequest>(parse_client_message(R"({"type":"command","command":"inspect","instrument":"x"})")).command.hold_s == 10);
  CHECK(request_of<CommandRequest>(parse_client_message(R"({"type":"command","command":"select_camera","camera":"bottom"})"))
            .command.camera == CameraId::Bottom);

  request_of<HeartbeatRequest>(parse_client_message(R"({"type":"heartbeat"})"));
  request_of<RequestControlRequest>(parse_client_message(R"({"type":"request_control"})"));
  request_of<ReleaseControlRequest>(parse_client_message(R"({"type":"release_control"})"));
  request_of<TakeOverRequest>(parse_client_message(R"({"type":"take_over"})"));
  CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"h264"})")).video == VideoPath::H264);
  CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"jpeg"})")).video == VideoPath::Jpeg);
  CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"geometry"})")).video == VideoPath::Geometry);
  CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"none"})")).video == VideoPath::None);
  CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"h264"})")).rendition == RenditionChoice::Auto);
  for (const RenditionChoice c : {RenditionChoice::Auto, RenditionChoice::Source, RenditionChoice::Low})
    CHECK(request_of<SubscribeRequest>(parse_client_message(R"({"type":"subscribe","video":"h264","rendition":")" +
                                                            std::string(to_string(c)) + "\"}"))
              .rendition == c);

  const ParsedMessage stop = parse_client_message(R"({"type":"command","id":1,"command":"emergency_stop"})");
  CHECK(is_emergency_stop(std::get<ClientRequest>(stop)));
  CHECK_FALSE(is_emergency_stop(std::get<ClientRequest>(land)));
}

TEST_CASE("lab: protocol: every refused input names what was wrong and what was expected") {
  // Not a typed message at all: refused before it counts against the rate limit.
  for (const char* text : {"{not json", "", "[1,2]", "42", R"("heartbeat")", R"({"command":"land"})", R"({"type":3})"}) {
    const ParsedMessage parsed = parse_client_message(text);
    REQUIRE(std::holds_alternative<Refusal>(parsed));
    CHECK_FALSE(std::get<Refusal>(parsed).typed);
  }
  CHECK(verdict_of("{not json") == "400 malformed JSON");
  CHECK(verdict_of("[1,2]") == "400 expected a JSON object");
  CHECK(verdict_of(R"({"command":"land"})") == "400 'type' (string) is required");
  CHECK(verdict_of(R"({"type":null})") == "400 'type' (string) is required");
  CHECK(verdict_of(R"({"type":"fly"})") ==
        "400 unknown message type 'fly' (expected command, heartbeat, request_control, release_control, take_over, "
        "subscribe)");

  // Commands.
  CHECK(verdict_of(R"({"type":"command"})") == "400 'command' (string) is required");
  CHECK(verdict_of(R"({"type":"command","command":5})") == "400 'command' (string) is required");
  CHECK(verdict_of(R"({"type":"command","command":"barrel_roll"})") ==
        "400 unknown command 'barrel_roll' (expected takeoff, inspect, find_teacher, stop_face_follow, return_home, land, "
        "stop, emergency_stop, select_camera, jog)");
  CHECK(verdict_of(R"({"type":"command","command":"land","speed":3})") == "400 unknown field 'speed' in a command");
  CHECK(verdict_of(R"({"type":"command","command":"land","id":"x"})") == "400 'id' must be an integer");
  CHECK(verdict_of(R"({"type":"command","command":"land","id":1.5})") == "400 'id' must be an integer");
  CHECK(verdict_of(R"({"type":"command","command":"inspect"})") == "400 inspect needs 'instrument' (string, an instrument id)");
  CHECK(verdict_of(R"({"type":"command","command":"inspect","instrument":3})") ==
        "400 inspect needs 'instrument' (string, an instrument id)");
  for (const char* hold : {"-1", "0", "600.5", "\"10\"", "null"})
    CHECK(verdict_of(std::string(R"({"type":"command","command":"inspect","instrument":"o","hold_s":)") + hold + "}") ==
          "400 'hold_s' must be a number in (0, 600] seconds");
  CHECK(verdict_of(R"({"type":"command","command":"inspect","instrument":"o","hold_s":600})") == "accepted");
  CHECK(verdict_of(R"({"type":"command","command":"land","instrument":"o"})") == "400 'instrument' and 'hold_s' belong to inspect only");
  CHECK(verdict_of(R"({"type":"command","command":"takeoff","hold_s":3})") == "400 'instrument' and 'hold_s' belong to inspect only");

  // The camera the drone streams: front or bottom, nothing else.
  for (const char* camera : {"", R"(,"camera":"down")", R"(,"camera":1)", R"(,"camera":null)", R"(,"camera":"Bottom")"})
    CHECK(verdict_of(std::string(R"({"type":"command","command":"select_camera")") + camera + "}") ==
          "400 select_camera needs 'camera' (string: front or bottom)");
  CHECK(verdict_of(R"({"type":"command","command":"select_camera","camera":"bottom","instrument":"o"})") ==
        "400 'instrument' and 'hold_s' belong to inspect only");
  CHECK(verdict_of(R"({"type":"command","command":"land","camera":"bottom"})") == "400 'camera' belongs to select_camera only");
  CHECK(verdict_of(R"({"type":"command","command":"select_camera","camera":"bottom"})") == "accepted");

  // The messages that carry nothing but their type.
  for (const char* type : {"heartbeat", "request_control", "release_control", "take_over"})
    CHECK(verdict_of(std::string(R"({"type":")") + type + R"(","extra":1})") == std::string("400 '") + type + "' takes no other field");
  const ParsedMessage typed = parse_client_message(R"({"type":"heartbeat","extra":1})");
  CHECK(std::get<Refusal>(typed).typed);

  // Subscriptions: the video path, nothing else.
  CHECK(verdict_of(R"({"type":"subscribe"})") == "400 subscribe needs 'video' (string: h264, jpeg, geometry or none)");
  CHECK(verdict_of(R"({"type":"subscribe","video":1})") == "400 subscribe needs 'video' (string: h264, jpeg, geometry or none)");
  CHECK(verdict_of(R"({"type":"subscribe","video":"H264"})") == "400 unknown video path 'H264' (expected h264, jpeg, geometry or none)");
  CHECK(verdict_of(R"({"type":"subscribe","video":"vp8"})") == "400 unknown video path 'vp8' (expected h264, jpeg, geometry or none)");
  CHECK(verdict_of(R"({"type":"subscribe","video":"h264","rate":3})") ==
        "400 unknown field 'rate' in subscribe (expected 'video' and optionally 'rendition')");
  // The H.264 rendition: auto (the default), source or low, on the h264 path only.
  for (const char* bad : {"\"LOW\"", "\"medium\"", "1", "null", "[\"low\"]"})
    CHECK(verdict_of(std::string(R"({"type":"subscribe","video":"h264","rendition":)") + bad + "}") ==
          "400 'rendition' must be auto, source or low");
  CHECK(verdict_of(R"({"type":"subscribe","video":"jpeg","rendition":"low"})") == "400 'rendition' belongs to the h264 path only");
}

TEST_CASE("lab: protocol: a jog is one bounded step, and its refusals say the bounds") {
  // Held by name: request_of returns a reference into the parsed message, which must outlive it.
  const ParsedMessage parsed = parse_client_message(R"({"type":"command","command":"jog","dz_m":0.2,"dyaw_deg":-15})");
  const auto& jog = request_of<CommandRequest>(parsed);
  CHECK(jog.command.kind == MissionCommandKind::Jog);
  CHECK(jog.command.dz_m == 0.2);
  CHECK(jog.command.dyaw_rad == Approx(-15 * 3.14159265358979 / 180));
  const auto refusal = [](const std::string& text) { return std::get<Refusal>(parse_client_message(text)).error; };
  CHECK(refusal(R"({"type":"command","command":"jog"})") == "jog needs a step: 'dx_m', 'dy_m', 'dz_m' (metres) or 'dyaw_deg'");
  CHECK(refusal(R"({"type":"command","command":"jog","dx_m":0.6})") == "'dx_m' must be a number in [-0.5, 0.5] m");
  CHECK(refusal(R"({"type":"command","command":"jog","dy_m":"1"})") == "'dy_m' must be a number in [-0.5, 0.5] m");
  CHECK(refusal(R"({"type":"command","command":"jog","dyaw_deg":90})") == "'dyaw_deg' must be a number in [-45, 45] degrees");
  CHECK(refusal(R"({"type":"command","command":"jog","dx_m":0.1,"hold_s":3})") == "'instrument' and 'hold_s' belong to inspect only");
  CHECK(refusal(R"({"type":"command","command":"land","dx_m":0.1})") == "'dx_m', 'dy_m', 'dz_m' and 'dyaw_deg' belong to jog only");
  CHECK(refusal(R"({"type":"command","command":"select_camera","camera":"front","dz_m":0.1})") ==
        "'dx_m', 'dy_m', 'dz_m' and 'dyaw_deg' belong to jog only");
  CHECK(refusal(R"({"type":"command","command":"jog","dz_m":0.1,"camera":"front"})") == "'camera' belongs to select_camera only");
}
