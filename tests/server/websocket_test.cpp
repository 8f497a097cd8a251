#include <catch2/catch.hpp>
#include <thread>

#include "server/video/frame_header.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;

namespace {
auto field_is(const std::string& key, const json& value) {
  return [key, value](const json& j) { return j.contains(key) && j[key] == value; };
}
}  // namespace

TEST_CASE("web: a WebSocket needs a session, commands need control, a spectator stops but may not cut the motors") {
  ServerFixture f;
  // No cookie: the upgrade is refused with 401.
  CHECK_THROWS(WsClient(f.port, "labo_session=forged"));

  WsClient alice(f.port, login_cookie(f.port, "alice", "alice-pw"));
  WsClient bob(f.port, login_cookie(f.port, "bob", "bob-pw"));
  const auto hello = alice.wait_for("hello");
  REQUIRE(hello);
  CHECK((*hello)["role"] == "student");
  CHECK((*hello)["instruments"][0]["id"] == "oscilloscope");

  alice.send(json{{"type", "command"}, {"id", 1}, {"command", "takeoff"}});
  auto ack = alice.wait_for("ack", field_is("id", 1));
  REQUIRE(ack);
  CHECK_FALSE((*ack)["accepted"]);
  CHECK((*ack)["reason"].get<std::string>().find("control") != std::string::npos);

  alice.send(json{{"type", "request_control"}});
  REQUIRE(alice.wait_for("notice", field_is("kind", "granted")));
  bob.send(json{{"type", "request_control"}});
  const auto queued = bob.wait_for("control", [](const json& j) { return j["you"]["position"] == 1; });
  REQUIRE(queued);
  CHECK((*queued)["controller"]["user"] == "alice");

  alice.send(json{{"type", "command"}, {"id", 2}, {"command", "takeoff"}});
  ack = alice.wait_for("ack", field_is("id", 2));
  REQUIRE(ack);
  CHECK((*ack)["accepted"]);
  alice.send(json{{"type", "command"}, {"id", 3}, {"command", "inspect"}, {"instrument", "oscilloscope"}, {"hold_s", 5}});
  REQUIRE(alice.wait_for("ack", field_is("id", 3)).value()["accepted"]);
  alice.send(json{{"type", "command"}, {"id", 4}, {"command", "inspect"}, {"instrument", "toaster"}});
  ack = alice.wait_for("ack", field_is("id", 4));
  CHECK_FALSE((*ack)["accepted"]);  // the flight side's own refusal, passed on
  CHECK((*ack)["reason"] == "no instrument 'toaster'");

  // Bob is a spectator: in a class of thirty one keypress must not drop the drone, so his motor cut
  // is refused with 403 and never reaches the drone...
  bob.send(json{{"type", "command"}, {"id", 9}, {"command", "emergency_stop"}});
  const auto refused = bob.wait_for("error", field_is("status", 403));
  REQUIRE(refused);
  CHECK((*refused)["error"].get<std::string>().find("send stop (hover, then land) instead") != std::string::npos);
  ack = bob.wait_for("ack", field_is("id", 9));
  REQUIRE(ack);
  CHECK_FALSE((*ack)["accepted"]);
  // ...but his stop acts without control, and everyone is told who stopped.
  bob.send(json{{"type", "command"}, {"id", 10}, {"command", "stop"}});
  REQUIRE(bob.wait_for("ack", field_is("id", 10)).value()["accepted"]);
  const auto stopped = alice.wait_for("event", field_is("kind", "stop"));
  REQUIRE(stopped);
  CHECK((*stopped)["user"] == "bob");
  CHECK((*stopped)["message"] == "stop by bob: hovering, then landing");
  // Alice holds control: her motor cut acts.
  alice.send(json{{"type", "command"}, {"id", 11}, {"command", "emergency_stop"}});
  REQUIRE(alice.wait_for("ack", field_is("id", 11)).value()["accepted"]);
  const auto cut = bob.wait_for("event", field_is("kind", "emergency"));
  REQUIRE(cut);
  CHECK((*cut)["user"] == "alice");
  const auto seen = f.flight.requests_seen();
  REQUIRE(seen.size() == 5);
  CHECK(seen[1].instrument == "oscilloscope");
  CHECK(seen[1].hold_s == 5);
  CHECK(seen[3].kind == MissionCommandKind::Stop);
  CHECK(seen.back().kind == MissionCommandKind::EmergencyStop);
}

TEST_CASE("web: WebSocket bad input gets a JSON error with its status") {
  ServerFixture f;
  WsClient c(f.port, login_cookie(f.port, "alice", "alice-pw"));
  const auto error_after = [&](const std::string& text) {
    c.send(text);
    auto e = c.wait_for("error");
    return e ? std::to_string((*e)["status"].get<int>()) + " " + (*e)["error"].get<std::string>() : std::string("none");
  };
  CHECK(error_after("{not json") == "400 malformed JSON");
  CHECK(error_after("[1,2]") == "400 expected a JSON object");
  CHECK(error_after(R"({"command":"land"})") == "400 'type' (string) is required");
  CHECK(error_after(R"({"type":"fly"})").find("400 unknown message type 'fly'") == 0);
  CHECK(error_after(R"({"type":"command","command":"barrel_roll"})").find("400 unknown command") == 0);
  CHECK(error_after(R"({"type":"command","command":"inspect"})").find("400 inspect needs 'instrument'") == 0);
  CHECK(error_after(R"({"type":"command","command":"land","speed":3})") == "400 unknown field 'speed' in a command");
  CHECK(error_after(R"({"type":"command","command":"land","id":"x"})") == "400 'id' must be an integer");
  CHECK(error_after(R"({"type":"command","command":"inspect","instrument":"oscilloscope","hold_s":-1})").find("400 'hold_s'") == 0);
  CHECK(error_after(R"({"type":"heartbeat","extra":1})") == "400 'heartbeat' takes no other field");
  CHECK(error_after(R"({"type":"take_over"})") == "403 only a teacher or an admin may take over");
}

TEST_CASE("web: a command flood is rate limited, but not the emergency stop") {
  ServerFixture f([](ServerSettings& s) {
    s.clients.commands_per_s = 1;
    s.clients.command_burst = 3;
  });
  WsClient c(f.port, login_cookie(f.port, "tess", "tess-pw"));  // a teacher may cut the motors without control
  for (int i = 0; i < 10; ++i) c.send(json{{"type", "heartbeat"}});
  const auto limited = c.wait_for("error", field_is("status", 429));
  REQUIRE(limited);
  c.send(json{{"type", "command"}, {"id", 77}, {"command", "emergency_stop"}});
  const auto ack = c.wait_for("ack", field_is("id", 77));
  REQUIRE(ack);
  CHECK((*ack)["accepted"]);
}

TEST_CASE("web: a teacher takes over, the student is told and queued first, turns end on the time limit") {
  ServerFixture f([](ServerSettings& s) {
    s.control.time_limit_s = 10;
    s.control.warnings_s = {9.5};
  });
  WsClient alice(f.port, login_cookie(f.port, "alice", "alice-pw"));
  WsClient tess(f.port, login_cookie(f.port, "tess", "tess-pw"));
  alice.send(json{{"type", "request_control"}});
  REQUIRE(alice.wait_for("notice", field_is("kind", "granted")));
  REQUIRE(alice.wait_for("notice", field_is("kind", "warning"), 3.0));  // 9.5 s before the end of a 10 s turn
  tess.send(json{{"type", "take_over"}});
  const auto ended = alice.wait_for("notice", field_is("kind", "ended"));
  REQUIRE(ended);
  CHECK((*ended)["reason"] == "taken over by tess");
  REQUIRE(tess.wait_for("notice", field_is("kind", "granted")));
  CHECK(alice.wait_for("control", [](const json& j) { return j["you"]["position"] == 1; }));
  tess.send(json{{"type", "release_control"}});
  REQUIRE(alice.wait_for("notice", field_is("kind", "granted")));
}

TEST_CASE("web: video frames reach every viewer as binary messages with the frame header") {
  ServerFixture f;
  WsClient a(f.port, login_cookie(f.port, "alice", "alice-pw"));
  WsClient b(f.port, login_cookie(f.port, "bob", "bob-pw"));
  REQUIRE(a.wait_for("hello"));
  REQUIRE(b.wait_for("hello"));
  f.flight.publish_frame(42);
  for (WsClient* c : {&a, &b}) {
    const auto frame = c->wait_for_frame();
    REQUIRE(frame);
    const auto header = FrameHeader::read(frame->data);
    REQUIRE(header);
    CHECK(header->frame_number == 42);
    CHECK(header->capture_unix_ms == 1.0e12);
    CHECK(static_cast<unsigned char>(frame->data[FrameHeader::kSize]) == 0xFF);  // JPEG SOI
  }
  f.flight.publish_event({"stage", "inspect", "2 approach", "inspect: 2 approach"});
  CHECK(a.wait_for("event", field_is("stage", "2 approach")));
}

TEST_CASE("web: a viewer that reads nothing costs bounded memory and is disconnected, others keep their video") {
  ServerFixture f([](ServerSettings& s) {
    s.clients.event_queue_messages = 8;
    s.clients.backlog_timeout_s = 1.0;
    s.clients.write_timeout_s = 2.0;
  });
  const StuckViewer stuck(f.port, login_cookie(f.port, "bob", "bob-pw"));

  WsClient good(f.port, login_cookie(f.port, "alice", "alice-pw"));
  REQUIRE(good.wait_for("hello"));
  int received = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::uint32_t i = 0; std::chrono::steady_clock::now() - start < std::chrono::seconds(5); ++i) {
    f.flight.publish_frame(i, 1);  // noisy frames: large JPEGs
    f.flight.publish_event({"log", "", "", std::string(512, 'x')});
    if (good.wait_for_frame(1.0)) ++received;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(received > 50);
  CHECK(f.server->metrics().ws_slow_disconnects.load() == 1);
  CHECK(f.server->metrics().ws_frames_skipped.load() > 0);
  CHECK(f.server->metrics().ws_clients.load() == 1);
}

TEST_CASE("web: an oversize WebSocket message is refused and the client disconnected") {
  ServerFixture f([](ServerSettings& s) { s.clients.max_message_bytes = 1024; });
  WsClient c(f.port, login_cookie(f.port, "alice", "alice-pw"));
  REQUIRE(c.wait_for("hello"));
  c.send(json{{"type", "heartbeat"}, {"pad", std::string(4000, 'x')}}.dump());
  // The server closes with code 1009 (message too big): reads fail instead of timing out on telemetry.
  bool closed = false;
  for (int i = 0; i < 100 && !closed; ++i) closed = !c.read(2.0);
  CHECK(closed);
}
