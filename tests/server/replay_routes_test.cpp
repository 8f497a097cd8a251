#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "drone/replay/recording.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

TEST_CASE("web: REST replay of a recording: started, watched, stopped, audited, and every refusal") {
  ServerFixture f;
  {
    replay::RecordingWriter w(f.settings.recordings_dir / "long.ldrec");  // 60 s of notes: plays until stopped
    w.note(0.0, "start");
    w.note(60.0, "end");
  }
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  REQUIRE(!root.empty());
  const auto start = [&](const std::string& name, const std::string& body, const std::string& who) {
    return http_call(f.port, verb::post, "/api/recordings/" + name + "/replay", body, who);
  };

  // Refused input, each with its reason.
  CHECK(start("long.ldrec", R"({"audience":"me"})", tess).status == 403);
  CHECK(start("long.ldrec", R"({"audience":"me"})", {}).status == 401);
  CHECK(start(".hidden", "", root).status == 400);
  CHECK(start("missing.ldrec", "", root).status == 404);
  const HttpResult junk = start("flight1.ldrec", "", root);  // "recorded bytes": no recording
  CHECK(junk.status == 422);
  CHECK_THAT(junk.json()["error"].get<std::string>(), Catch::Contains("flight1.ldrec"));
  CHECK(start("long.ldrec", "{", root).status == 400);
  CHECK(start("long.ldrec", R"({"audience":"class"})", root).status == 400);
  CHECK(start("long.ldrec", R"({"audience":1})", root).status == 400);
  CHECK(start("long.ldrec", R"({"volume":3})", root).status == 400);
  CHECK(start("long.ldrec", R"({"speed":100})", root).status == 422);
  CHECK(start("long.ldrec", R"({"speed":"fast"})", root).status == 422);
  CHECK(http_call(f.port, verb::get, "/api/recordings/long.ldrec/replay", {}, root).status == 405);
  CHECK(http_call(f.port, verb::post, "/api/recordings/long.ldrec/play", {}, root).status == 404);
  CHECK(http_call(f.port, verb::delete_, "/api/replay", {}, root).status == 404);  // nothing plays
  CHECK(http_call(f.port, verb::put, "/api/replay", {}, root).status == 405);
  CHECK(http_call(f.port, verb::get, "/api/replay", {}, root).json()["replay"].is_null());

  const HttpResult started = start("long.ldrec", R"({"audience":"everyone","speed":2})", root);
  REQUIRE(started.status == 200);
  const json replay = started.json()["replay"];
  CHECK(replay["name"] == "long.ldrec");
  CHECK(replay["by"] == "root");
  CHECK(replay["audience"] == "everyone");
  CHECK(replay["speed"] == 2.0);
  CHECK(replay["state"] == "playing");
  const HttpResult again = start("long.ldrec", "", root);
  CHECK(again.status == 409);
  CHECK_THAT(again.json()["error"].get<std::string>(), Catch::Contains("DELETE /api/replay"));
  CHECK(http_call(f.port, verb::get, "/api/replay", {}, root).json()["replay"]["state"] == "playing");

  REQUIRE(http_call(f.port, verb::delete_, "/api/replay", {}, root).status == 200);
  json status;
  for (int i = 0; i < 100; ++i) {
    status = http_call(f.port, verb::get, "/api/replay", {}, root).json()["replay"];
    if (status["state"] != "playing") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(status["state"] == "stopped");

  // Who started and stopped what, in the audit log.
  const json audit = http_call(f.port, verb::get, "/api/audit?limit=50", {}, root).json();
  int starts = 0, stops = 0;
  for (const json& e : audit["entries"]) {
    starts += e.value("action", "") == "replay_start" && e.value("target", "") == "long.ldrec" && e.value("result", "") == "accepted";
    stops += e.value("action", "") == "replay_stop" && e.value("result", "") == "accepted";
  }
  CHECK(starts == 1);
  CHECK(stops == 1);
}
