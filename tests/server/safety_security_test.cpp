#include <catch2/catch.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <fstream>

#include "server/audit/audit_log.hpp"
#include "server/auth/session_store.hpp"
#include "server/http/origin_check.hpp"
#include "server/http/tls_context.hpp"
#include "tests/server/support/self_signed_cert.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using http::verb;

namespace {

auto field_is(const std::string& key, const json& value) {
  return [key, value](const json& j) { return j.contains(key) && j[key] == value; };
}

std::vector<json> audit_entries(unsigned short port, const std::string& admin, const std::string& query = {}) {
  const HttpResult r = http_call(port, verb::get, "/api/audit" + query, {}, admin);
  REQUIRE(r.status == 200);
  return r.json()["entries"].get<std::vector<json>>();
}

}  // namespace

TEST_CASE("web: REST stop and emergency stop: a spectator's motor cut is refused with 403, their stop lands") {
  ServerFixture f;
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const std::string bob = login_cookie(f.port, "bob", "bob-pw");
  const std::string tess = login_cookie(f.port, "tess", "tess-pw");
  const HttpResult cut = http_call(f.port, verb::post, "/api/emergency_stop", {}, alice);
  CHECK(cut.status == 403);
  CHECK(cut.json()["error"].get<std::string>().find("POST /api/stop (hover, then land) instead") != std::string::npos);
  const HttpResult stop = http_call(f.port, verb::post, "/api/stop", {}, alice);
  CHECK(stop.status == 200);
  CHECK(stop.json()["accepted"] == true);
  CHECK(http_call(f.port, verb::post, "/api/emergency_stop", "{}", tess).status == 200);  // a teacher may
  // Refused inputs: no session, wrong method, wrong content type, a field the route does not take.
  CHECK(http_call(f.port, verb::post, "/api/stop").status == 401);
  CHECK(http_call(f.port, verb::get, "/api/stop", {}, alice).status == 405);
  CHECK(http_call(f.port, verb::post, "/api/stop", "now", alice, "text/plain").status == 415);
  const HttpResult extra = http_call(f.port, verb::post, "/api/stop", R"({"force":true})", alice);
  CHECK(extra.status == 400);
  CHECK(extra.json()["error"].get<std::string>().find("unknown field 'force'") == 0);
  CHECK(http_call(f.port, verb::post, "/api/stop", "{", alice).status == 400);

  // The student holding control (on a WebSocket) may cut the motors over REST too.
  WsClient ws(f.port, bob);
  ws.send(json{{"type", "request_control"}});
  REQUIRE(ws.wait_for("notice", field_is("kind", "granted")));
  CHECK(http_call(f.port, verb::post, "/api/emergency_stop", {}, bob).status == 200);
  const auto seen = f.flight.requests_seen();
  REQUIRE(seen.size() == 3);
  CHECK(seen[0].kind == MissionCommandKind::Stop);
  CHECK(seen[1].kind == MissionCommandKind::EmergencyStop);
}

TEST_CASE("web: the audit log keeps every command and admin action, newest first, for admins only") {
  ServerFixture f;
  const std::string root = login_cookie(f.port, "root", "root-pw");
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  CHECK(login_cookie(f.port, "alice", "wrong").empty());
  WsClient ws(f.port, alice);
  ws.send(json{{"type", "command"}, {"id", 1}, {"command", "takeoff"}});  // no control: refused
  REQUIRE(ws.wait_for("ack", field_is("id", 1)));
  ws.send(json{{"type", "command"}, {"id", 2}, {"command", "emergency_stop"}});  // a spectator's cut: refused
  REQUIRE(ws.wait_for("ack", field_is("id", 2)));
  CHECK(http_call(f.port, verb::delete_, "/api/instruments/nothing", {}, root).status == 404);

  const std::vector<json> entries = audit_entries(f.port, root);
  REQUIRE(entries.size() == 6);  // 3 logins (one failed), 2 commands, 1 delete
  const json& newest = entries[0];
  CHECK(newest["user"] == "root");
  CHECK(newest["role"] == "admin");
  CHECK(newest["action"] == "instrument_delete");
  CHECK(newest["target"] == "nothing");
  CHECK(newest["result"] == "refused");
  CHECK(newest["detail"].get<std::string>().find("404") == 0);
  CHECK(newest["time"].get<std::string>().size() == 24);  // 2026-01-31T14:05:09.123Z
  CHECK(entries[1]["target"] == "emergency_stop");
  CHECK(entries[1]["result"] == "refused");
  CHECK(entries[2]["target"] == "takeoff");
  CHECK(entries[2]["detail"].get<std::string>().find("control") != std::string::npos);
  CHECK(entries[5]["action"] == "login");

  // Pages.
  const HttpResult page = http_call(f.port, verb::get, "/api/audit?offset=2&limit=2", {}, root);
  REQUIRE(page.status == 200);
  CHECK(page.json()["total"] == 6);
  CHECK(page.json()["entries"].size() == 2);
  CHECK(page.json()["entries"][0]["target"] == "takeoff");
  CHECK(audit_entries(f.port, root, "?offset=6").empty());
  // Refused inputs.
  CHECK(http_call(f.port, verb::get, "/api/audit", {}, alice).status == 403);
  CHECK(http_call(f.port, verb::get, "/api/audit").status == 401);
  CHECK(http_call(f.port, verb::post, "/api/audit", "{}", root).status == 405);
  for (const std::string q : {"?limit=0", "?limit=501", "?offset=-1", "?offset=x", "?limit=2.5"}) {
    const HttpResult bad = http_call(f.port, verb::get, "/api/audit" + q, {}, root);
    CHECK(bad.status == 400);
    CHECK(bad.json()["error"].get<std::string>().find("query parameter") == 0);
  }
  // The file itself: one JSON object per line, only ever appended to.
  std::ifstream in(f.settings.audit_log);
  int lines = 0;
  for (std::string line; std::getline(in, line); ++lines) CHECK(json::parse(line, nullptr, false).is_object());
  CHECK(lines == 6);
}

TEST_CASE("web: a WebSocket from another origin is refused with 403") {
  CHECK(origin_refusal("", "lab:8080", "").empty());  // scripts send no Origin
  CHECK(origin_refusal("http://lab:8080", "lab:8080", "").empty());
  CHECK(origin_refusal("HTTPS://LAB:8080/", "lab:8080", "").empty());
  CHECK_FALSE(origin_refusal("http://evil.example", "lab:8080", "").empty());
  CHECK_FALSE(origin_refusal("http://lab:8080.evil.example", "lab:8080", "").empty());
  CHECK_FALSE(origin_refusal("null", "lab:8080", "").empty());
  CHECK_FALSE(origin_refusal("file://lab:8080", "lab:8080", "").empty());
  CHECK(origin_refusal("https://lab.example.org", "10.0.0.5:8080", "https://lab.example.org").empty());
  CHECK_FALSE(origin_refusal("http://10.0.0.5:8080", "10.0.0.5:8080", "https://lab.example.org").empty());

  ServerFixture f;
  const std::string alice = login_cookie(f.port, "alice", "alice-pw");
  const std::string own = "http://127.0.0.1:" + std::to_string(f.port);
  WsClient same(f.port, alice, own);
  CHECK(same.wait_for("hello"));
  try {
    WsClient other(f.port, alice, "http://evil.example");
    FAIL("the upgrade from another origin was accepted");
  } catch (const beast::system_error& e) {
    CHECK(e.code() == beast::websocket::error::upgrade_declined);
  }
}

TEST_CASE("web: sessions survive a restart by their token's hash, and end with their user or role") {
  const auto dir = fresh_temp_dir("sessions");
  const auto file = dir / "sessions.json";
  const auto account = [](const std::string& name, Role role) {
    return UserAccount{name, role, PasswordHash::create(name + "-pw", PasswordHash::kMinIterations).encode()};
  };
  const std::vector<UserAccount> users{account("alice", Role::Student), account("bob", Role::Student), account("tess", Role::Teacher)};
  std::string alice, bob, tess, idle;
  {
    SessionStore store(users, 100.0, 60.0, file);
    alice = store.login("alice", "alice-pw", "a", 1000).session.token;
    bob = store.login("bob", "bob-pw", "b", 1000).session.token;
    tess = store.login("tess", "tess-pw", "c", 1000).session.token;
    idle = store.login("alice", "alice-pw", "d", 900).session.token;
    REQUIRE(store.authenticate(alice, 1050));
    store.save_if_changed(1050, true);
  }
  std::ifstream in(file);
  const std::string saved((std::istreambuf_iterator<char>(in)), {});
  CHECK(saved.find(alice) == std::string::npos);  // the file logs nobody in
  CHECK(saved.find(sha256_hex(alice)) != std::string::npos);

  // Restarted with bob removed and tess now an admin.
  SessionStore restarted({users[0], account("tess", Role::Admin)}, 100.0, 60.0, file);
  const auto again = restarted.authenticate(alice, 1100);
  REQUIRE(again);
  CHECK(again->user == "alice");
  CHECK(again->created_s == 1000);
  CHECK_FALSE(restarted.authenticate(bob, 1100));
  CHECK_FALSE(restarted.authenticate(tess, 1100));
  CHECK_FALSE(restarted.authenticate(idle, 1100));  // idle since 900: expired cleanly
  CHECK(restarted.end(again->id));
  CHECK_FALSE(restarted.authenticate(alice, 1101));
  std::filesystem::remove_all(dir);
}

TEST_CASE("web: over TLS the pages, the API and the WebSocket are served and the cookie is Secure") {
  const auto dir = fresh_temp_dir("tls");
  const SelfSignedCert cert = make_self_signed_cert(dir);
  ServerFixture f([&](ServerSettings& s) { s.tls = {cert.cert_file, cert.key_file}; });
  asio::ssl::context client_tls(asio::ssl::context::tls_client);
  client_tls.load_verify_file(cert.cert_file.string());  // trust the test's own certificate only
  client_tls.set_verify_mode(asio::ssl::verify_peer);
  asio::io_context io;
  const auto connect = [&](auto& stream) {
    beast::get_lowest_layer(stream).connect({asio::ip::make_address("127.0.0.1"), f.port});
    stream.handshake(asio::ssl::stream_base::client);
  };
  beast::ssl_stream<beast::tcp_stream> https(io, client_tls);
  connect(https);
  http::request<http::string_body> login{verb::post, "/api/login", 11};
  login.set(http::field::host, "127.0.0.1:" + std::to_string(f.port));
  login.set(http::field::content_type, "application/json");
  login.body() = R"({"user":"alice","password":"alice-pw"})";
  login.prepare_payload();
  http::write(https, login);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(https, buffer, res);
  REQUIRE(res.result_int() == 200);
  const std::string set_cookie(res[http::field::set_cookie]);
  CHECK(set_cookie.find("; Secure") != std::string::npos);
  CHECK(set_cookie.find("HttpOnly") != std::string::npos);

  beast::websocket::stream<beast::ssl_stream<beast::tcp_stream>> wss(io, client_tls);
  connect(wss.next_layer());
  const std::string cookie = set_cookie.substr(0, set_cookie.find(';'));
  wss.set_option(beast::websocket::stream_base::decorator([&](beast::websocket::request_type& r) {
    r.set(http::field::cookie, cookie);
    r.set(http::field::origin, "https://127.0.0.1:" + std::to_string(f.port));
  }));
  wss.handshake("127.0.0.1:" + std::to_string(f.port), "/ws");
  beast::flat_buffer msg;
  wss.read(msg);
  CHECK(json::parse(beast::buffers_to_string(msg.data()))["type"] == "hello");

  // Plain HTTP to the TLS port gets no answer.
  CHECK_THROWS(http_call(f.port, verb::get, "/api/health"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("web: a TLS setting naming a missing file, or a key that is not the certificate's, is refused") {
  const auto dir = fresh_temp_dir("tls_bad");
  const SelfSignedCert a = make_self_signed_cert(dir);
  std::filesystem::create_directories(dir / "b");
  const SelfSignedCert b = make_self_signed_cert(dir / "b");
  const auto config = [&](const json& tls) {
    return ConfigDocument::parse(json{{"tls", tls}}.dump(), "test.json");
  };
  const auto doc = config({{"cert_file", (dir / "none.pem").string()}, {"key_file", a.key_file.string()}});
  CHECK_THROWS_WITH(read_server_settings(doc.root(), dir), Catch::Contains("tls.cert_file") && Catch::Contains("no such file"));
  CHECK_THROWS_WITH(make_tls_context({a.cert_file, b.key_file}), Catch::Contains("key values mismatch"));
  CHECK(make_tls_context({a.cert_file, a.key_file}));
  std::filesystem::remove_all(dir);
}
