#include <catch2/catch.hpp>

#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

TEST_CASE("web: REST video: anyone logged in reads the drone's video, only an admin sets its bit rate, every bad input refused") {
  ServerFixture f;
  const std::string student = login_cookie(f.port, "alice", "alice-pw");
  const std::string teacher = login_cookie(f.port, "tess", "tess-pw");
  const std::string admin = login_cookie(f.port, "root", "root-pw");

  const HttpResult got = http_call(f.port, verb::get, "/api/video", {}, student);
  REQUIRE(got.status == 200);
  CHECK(got.json()["bottom_camera"] == true);
  CHECK(got.json()["adjustable_bitrate"] == true);
  CHECK(got.json()["bitrate_kbps"] == 4000);
  CHECK(got.json()["min_bitrate_kbps"] == 250);
  CHECK(got.json()["max_bitrate_kbps"] == 4000);
  CHECK(got.json()["low_rendition_kbps"] == f.settings.video.low_rendition_kbps);
  CHECK(http_call(f.port, verb::get, "/api/video").status == 401);
  CHECK(http_call(f.port, verb::post, "/api/video", "{}", student).status == 405);

  const auto put = [&](const std::string& body, const std::string& cookie, const std::string& type = "application/json") {
    return http_call(f.port, verb::put, "/api/video/bitrate", body, cookie, type);
  };
  CHECK(put(R"({"kbps":2000})", "").status == 401);
  CHECK(put(R"({"kbps":2000})", student).status == 403);
  CHECK(put(R"({"kbps":2000})", teacher).status == 403);
  CHECK(put(R"({"kbps":2000})", admin, "text/plain").status == 415);
  CHECK(http_call(f.port, verb::get, "/api/video/bitrate", {}, admin).status == 405);
  const auto refusal = [&](const std::string& body) {
    const HttpResult r = put(body, admin);
    return std::to_string(r.status) + " " + r.json().value("error", "");
  };
  CHECK(refusal("{kbps") == "400 malformed JSON");
  CHECK(refusal("[2000]") == "400 expected a JSON object {\"kbps\": integer}");
  CHECK(refusal(R"({"kbps":2000,"mode":"manual"})") == "400 unknown field 'mode' (expected 'kbps')");
  for (const char* bad : {"{}", R"({"kbps":"2000"})", R"({"kbps":2000.5})", R"({"kbps":null})", R"({"kbps":true})"})
    CHECK(refusal(bad) == "400 'kbps' (integer, kbit/s) is required");
  CHECK(refusal(R"({"kbps":249})") == "400 'kbps' must be in [250, 4000] for scripted AR.Drone, got 249");
  CHECK(refusal(R"({"kbps":4001})") == "400 'kbps' must be in [250, 4000] for scripted AR.Drone, got 4001");
  CHECK(refusal(R"({"kbps":-1})") == "400 'kbps' must be in [250, 4000] for scripted AR.Drone, got -1");
  CHECK(f.flight.video_capabilities().bitrate_kbps == 4000);  // nothing refused reached the drone

  const HttpResult ok = put(R"({"kbps":2000})", admin);
  REQUIRE(ok.status == 200);
  CHECK(ok.json()["bitrate_kbps"] == 2000);
  CHECK(f.flight.video_capabilities().bitrate_kbps == 2000);

  // Every request of an admin or not, accepted or refused, is in the audit log with the rate asked.
  const auto actions = audit_actions(f);
  const auto count = [&](const std::string& line) { return std::count(actions.begin(), actions.end(), line); };
  CHECK(count("video_bitrate 2000 ok") == 1);
  CHECK(count("video_bitrate 2000 refused") == 3);  // the student, the teacher, the unknown field
  CHECK(count("video_bitrate 249 refused") == 1);
  CHECK(count("video_bitrate  refused") == 6);  // no number in the body: malformed, an array, {}, "2000", null, true
}

TEST_CASE("web: REST video: a drone whose link has no bit-rate setting refuses it with 409 and says why") {
  ServerFixture f;
  f.flight.video = {"Tello", false, "a Tello has one camera, looking forward: there is no bottom camera to stream", false, 0, 0, 0};
  const std::string admin = login_cookie(f.port, "root", "root-pw");
  const HttpResult got = http_call(f.port, verb::get, "/api/video", {}, admin);
  CHECK(got.json()["bottom_camera"] == false);
  CHECK(got.json()["no_bottom_camera"].get<std::string>().find("no bottom camera") != std::string::npos);
  const HttpResult r = http_call(f.port, verb::put, "/api/video/bitrate", R"({"kbps":2000})", admin);
  CHECK(r.status == 409);
  CHECK(r.json()["error"] == "Tello: the link cannot ask the drone for a video bit rate");
}
