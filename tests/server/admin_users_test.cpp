#include <catch2/catch.hpp>
#include <fstream>

#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

namespace {

json config_users(const ServerFixture& f) {
  std::ifstream in(f.config_file);
  return json::parse(in)["server"]["users"];
}

std::string error_of(const HttpResult& r) { return std::to_string(r.status) + " " + r.json().value("error", ""); }

}  // namespace

TEST_CASE("web: an admin adds a user who logs in at once, and the config file keeps them") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const HttpResult added = http_call(f.port, verb::post, "/api/users", R"({"name":"carol","role":"student","password":"carol-pass"})", root);
  REQUIRE(added.status == 201);
  CHECK(added.json()["added"] == "carol");
  CHECK_FALSE(login_cookie(f.port, "carol", "carol-pass").empty());
  const json users = config_users(f);
  CHECK(users.back()["name"] == "carol");
  CHECK(users.back()["password_hash"].get<std::string>().rfind("pbkdf2-sha256$", 0) == 0);
  CHECK_FALSE(std::filesystem::exists(f.config_file.string() + ".tmp"));
  CHECK(http_call(f.port, verb::get, "/api/users", {}, root).json()["users"].dump().find("carol") != std::string::npos);
}

TEST_CASE("web: adding a user refuses bad input with its status") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const auto add = [&](const std::string& body, const std::string& cookie = {}, const std::string& type = "application/json") {
    return http_call(f.port, verb::post, "/api/users", body, cookie.empty() ? root : cookie, type);
  };
  CHECK(error_of(add(R"({"name":"carol","role":"student"})")) == "400 a new user needs 'name', 'role' and 'password' (strings)");
  CHECK(error_of(add(R"({"name":"carol","role":"student","password":"carol-pass","admin":true})")).find("400 unknown field 'admin'") == 0);
  CHECK(add("{").status == 400);
  CHECK(add(R"({"name":"carol","role":"pilot","password":"carol-pass"})").status == 422);
  CHECK(error_of(add(R"({"name":"carol","role":"student","password":"short"})")) == "422 'password' must be 8 to 256 characters");
  CHECK(add(R"({"name":"carol","role":"student","password":5})").status == 400);
  CHECK(add(R"({"name":"../etc","role":"student","password":"carol-pass"})").status == 422);
  CHECK(error_of(add(R"({"name":"alice","role":"student","password":"alice-pass"})")) == "409 user 'alice' exists");
  CHECK(add(R"({"name":"carol","role":"student","password":"carol-pass"})", alice).status == 403);
  CHECK(http_call(f.port, verb::post, "/api/users", R"({"name":"carol"})").status == 401);
  CHECK(add("name=carol", {}, "application/x-www-form-urlencoded").status == 415);
  CHECK(http_call(f.port, verb::get, "/api/users/alice", {}, root).status == 405);
  CHECK(config_users(f).size() == 4);  // nothing refused was written
}

TEST_CASE("web: an admin re-roles, resets and removes users, whose sessions and WebSockets end") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string bob = login_cookie(f.port, "bob", "bob-pw");
  WsClient bob_ws(f.port, bob);
  REQUIRE(bob_ws.wait_for("hello"));
  const auto put = [&](const std::string& user, const std::string& body) {
    return http_call(f.port, verb::put, "/api/users/" + user, body, root);
  };
  CHECK(put("bob", R"({"role":"teacher"})").status == 200);
  CHECK(http_call(f.port, verb::get, "/api/me", {}, bob).status == 401);  // re-roled: logged out
  bool closed = false;  // and his WebSocket closed (telemetry would otherwise arrive 10 times a second)
  for (int i = 0; i < 100 && !closed; ++i) closed = !bob_ws.read(1.0);
  CHECK(closed);
  const std::string bob_teacher = login_cookie(f.port, "bob", "bob-pw");
  CHECK(http_call(f.port, verb::get, "/api/me", {}, bob_teacher).json()["role"] == "teacher");

  CHECK(put("bob", R"({"password":"new-bob-pass"})").status == 200);
  CHECK(login_cookie(f.port, "bob", "bob-pw").empty());
  CHECK_FALSE(login_cookie(f.port, "bob", "new-bob-pass").empty());

  CHECK(error_of(put("bob", "{}")) == "400 send 'role', 'password' or both");
  CHECK(put("bob", R"({"name":"robert"})").status == 400);
  CHECK(put("nobody", R"({"role":"admin"})").status == 404);
  CHECK(put("bob", R"({"role":"pilot"})").status == 422);
  CHECK(error_of(put("root", R"({"role":"student"})")) == "409 you may not change your own role");

  CHECK(http_call(f.port, verb::delete_, "/api/users/bob", {}, root).status == 200);
  CHECK(login_cookie(f.port, "bob", "new-bob-pass").empty());
  CHECK(http_call(f.port, verb::delete_, "/api/users/bob", {}, root).status == 404);
  CHECK(error_of(http_call(f.port, verb::delete_, "/api/users/root", {}, root)) == "409 you may not remove yourself");
  CHECK(http_call(f.port, verb::delete_, "/api/users/alice", {}, login_cookie(f.port, "tess", "tess-pw")).status == 403);
  CHECK(config_users(f).size() == 3);
}

TEST_CASE("web: an admin ends a session, and a config change says what applies now and what at the next start") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  WsClient ws(f.port, alice);
  REQUIRE(ws.wait_for("hello"));
  const std::string id = http_call(f.port, verb::get, "/api/me", {}, alice).json()["session"];
  CHECK(http_call(f.port, verb::delete_, "/api/sessions/" + id, {}, tess).status == 403);
  const HttpResult ended = http_call(f.port, verb::delete_, "/api/sessions/" + id, {}, root);
  REQUIRE(ended.status == 200);
  CHECK(ended.json()["connections_closed"] == 1);
  CHECK(http_call(f.port, verb::get, "/api/me", {}, alice).status == 401);
  CHECK(http_call(f.port, verb::delete_, "/api/sessions/" + id, {}, root).status == 404);
  CHECK(http_call(f.port, verb::post, "/api/sessions/" + id, "{}", root).status == 405);

  json doc = http_call(f.port, verb::get, "/api/config", {}, root).json();
  doc["server"]["port"] = 8282;
  doc["server"]["users"].erase(0);  // the config file's first user
  const HttpResult put = http_call(f.port, verb::put, "/api/config", doc.dump(), root);
  REQUIRE(put.status == 200);
  CHECK(put.json()["applied"] == json::array({"server.users"}));
  CHECK(put.json()["restart_required"] == json::array({"server.port"}));
}
