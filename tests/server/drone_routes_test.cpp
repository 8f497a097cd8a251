#include <catch2/catch.hpp>

#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

TEST_CASE("web: REST set-down: only an admin says the drone is on its platform, refused in flight, bad input refused") {
  ServerFixture f;
  const std::string student = login_cookie(f.port, "alice", "alice-pw");
  const std::string admin = login_cookie(f.port, "root", "root-pw");
  f.flight.edit_telemetry([](FlightTelemetry& t) { t.unobserved_flight_s = 7.1; });
  CHECK(http_call(f.port, verb::get, "/api/status", {}, admin).json()["unobserved_flight_s"] == 7.1);

  const auto post = [&](const std::string& body, const std::string& cookie) {
    const HttpResult r = http_call(f.port, verb::post, "/api/drone/set-down", body, cookie);
    return std::to_string(r.status) + " " + (r.status == 200 ? r.json().value("reason", "") : r.json().value("error", ""));
  };
  CHECK(post("", "").rfind("401 ", 0) == 0);
  CHECK(post("", student) == "403 role student may not say where the drone is");
  CHECK(http_call(f.port, verb::get, "/api/drone/set-down", {}, admin).status == 405);
  CHECK(post("{oops", admin) == "400 malformed JSON");
  CHECK(post(R"({"x": 1.0})", admin) == "400 expected no body or {} (the platform is the lab file's base)");
  CHECK(post("[]", admin) == "400 expected no body or {} (the platform is the lab file's base)");
  f.flight.edit_telemetry([](FlightTelemetry& t) { t.flying = true; });
  CHECK(post("", admin) == "409 set-down: the drone is flying (flying); land it, then set it on its platform");
  CHECK(f.flight.set_downs == 0);  // nothing refused reached the flight software

  f.flight.edit_telemetry([](FlightTelemetry& t) { t.flying = false; });
  CHECK(post("{}", admin) == "200 the drone was set on its platform: its place is the base's again");
  CHECK(f.flight.set_downs == 1);
  CHECK(http_call(f.port, verb::get, "/api/status", {}, admin).json()["unobserved_flight_s"] == 0.0);

  const auto actions = audit_actions(f);
  const auto count = [&](const std::string& line) { return std::count(actions.begin(), actions.end(), line); };
  CHECK(count("drone_set_down platform ok") == 1);
  CHECK(count("drone_set_down platform refused") == 5);  // the student, malformed, a field, an array, in flight
}
