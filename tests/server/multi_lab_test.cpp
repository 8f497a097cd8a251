#include <catch2/catch.hpp>
#include <fstream>

#include "server/api/lab_directory.hpp"
#include "server/auth/session_store.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;

namespace {

const std::string kTwoLabs = R"({"labs": [
  {"id": "lab1", "name": "Electronics 1", "url": "http://127.0.0.1:8081/", "janus": {"url": "ws://{host}:8188/", "mountpoint": 1}},
  {"id": "lab2", "name": "Electronics 2", "url": "http://127.0.0.1:8082/"}]})";

std::string refusal(const std::string& text, const std::string& self = "lab1") {
  try {
    LabDirectory::parse(text, self, "labs.json");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

SessionSigner signer(char fill) { return SessionSigner(std::vector<unsigned char>(32, static_cast<unsigned char>(fill))); }

UserAccount account(const std::string& name, Role role) {
  return {name, role, PasswordHash::create(name + "-pw", PasswordHash::kMinIterations).encode()};
}

}  // namespace

TEST_CASE("web: several labs: the lab directory names each lab and its Janus mount point") {
  const json dir = json::parse(LabDirectory::parse(kTwoLabs, "lab2", "labs.json").json());
  CHECK(dir["self"] == "lab2");
  REQUIRE(dir["labs"].size() == 2);
  CHECK(dir["labs"][0]["janus"] == json{{"url", "ws://{host}:8188/"}, {"mountpoint", 1}});
  CHECK_FALSE(dir["labs"][1].contains("janus"));
  CHECK(json::parse(LabDirectory().json()) == json{{"self", nullptr}, {"labs", json::array()}});
}

TEST_CASE("web: several labs: a bad lab directory is refused with the entry, the field and what was expected") {
  CHECK(refusal("[]") == "lab directory labs.json: top level: not a JSON object {\"labs\": [...]}");
  CHECK(refusal(R"({"labs": []})") == "lab directory labs.json: labs: expected a non-empty array of labs");
  CHECK(refusal(R"({"labs": [{"id": "Lab 1", "name": "a", "url": "http://h/"}]})") ==
        "lab directory labs.json: labs[0].id: 'Lab 1': expected 1 to 32 of a-z, 0-9, _ and -");
  CHECK(refusal(R"({"labs": [{"id": "lab1", "name": "a", "url": "ftp://h/"}]})").find("labs[0].url: 'ftp://h/': expected an http") !=
        std::string::npos);
  CHECK(refusal(R"({"labs": [{"id": "lab1", "name": "a", "url": "http://h/", "port": 1}]})") ==
        "lab directory labs.json: labs[0]: unknown key 'port' (expected id, janus, name, url)");
  CHECK(refusal(R"({"labs": [{"id": "lab1", "name": "a", "url": "http://h/"}, {"id": "lab1", "name": "b", "url": "http://h/"}]})") ==
        "lab directory labs.json: labs[1].id: 'lab1' twice");
  CHECK(refusal(R"({"labs": [{"id": "lab1", "name": "a", "url": "http://h/", "janus": {"url": "http://h:8088/janus", "mountpoint": 1}}]})")
            .find("labs[0].janus.url: 'http://h:8088/janus': expected a ws:// or wss:// URL") != std::string::npos);
  CHECK(refusal(R"({"labs": [{"id": "lab1", "name": "a", "url": "http://h/", "janus": {"url": "ws://h/", "mountpoint": 0}}]})") ==
        "lab directory labs.json: labs[0].janus.mountpoint: expected the streaming mount point's id, an integer from 1");
  CHECK(refusal(kTwoLabs, "lab3") == "lab directory labs.json: this lab's id 'lab3' (--lab-id) is not one of its labs");
}

TEST_CASE("web: several labs: a signed session token verifies with the same key only, unaltered and unexpired") {
  const SessionSigner a = signer('a');
  const std::string token = a.issue("alice", Role::Teacher, 2000.0);
  const auto claims = a.verify(token, 1000.0);
  REQUIRE(claims);
  CHECK(claims->user == "alice");
  CHECK(claims->role == Role::Teacher);
  CHECK_FALSE(a.verify(token, 2000.0));           // expired
  CHECK_FALSE(signer('b').verify(token, 1000.0));  // another front's key
  std::string promoted = token;
  promoted.replace(promoted.find(".teacher."), 9, ".admin.");
  CHECK_FALSE(a.verify(promoted, 1000.0));
  CHECK_FALSE(a.verify("s1.abc", 1000.0));
  CHECK_FALSE(a.verify("", 1000.0));
  CHECK(a.issue("alice", Role::Teacher, 2000.0) != token);  // a fresh nonce each login

  const auto dir = fresh_temp_dir("key");
  std::ofstream(dir / "short.key") << "0123456789\n";
  CHECK_THROWS_WITH(SessionSigner::from_key_file(dir / "short.key"), Catch::Contains("10 bytes, expected at least 32"));
  CHECK_THROWS_WITH(SessionSigner::from_key_file(dir / "missing.key"), Catch::Contains("missing.key: cannot be read"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("web: several labs: a login at one lab is a session at another sharing its key, until logged out there") {
  SessionStore lab1({account("alice", Role::Student), account("tess", Role::Teacher)}, 3600.0, 60.0);
  SessionStore lab2({account("alice", Role::Student), account("tess", Role::Student)}, 3600.0, 60.0);
  SessionStore elsewhere({account("alice", Role::Student)}, 3600.0, 60.0);
  lab1.share_with(signer('k'));
  lab2.share_with(signer('k'));
  elsewhere.share_with(signer('z'));

  const LoginResult alice = lab1.login("alice", "alice-pw", "127.0.0.1", 0.0);
  REQUIRE(alice.outcome == LoginOutcome::Ok);
  const auto at_lab2 = lab2.authenticate(alice.session.token, 5.0);
  REQUIRE(at_lab2);
  CHECK(at_lab2->user == "alice");
  CHECK(lab2.sessions(5.0).size() == 1);
  CHECK_FALSE(elsewhere.authenticate(alice.session.token, 5.0));

  // tess is a teacher at lab1 and a student at lab2: lab2 refuses the teacher's token.
  const LoginResult tess = lab1.login("tess", "tess-pw", "127.0.0.1", 0.0);
  CHECK_FALSE(lab2.authenticate(tess.session.token, 5.0));

  lab2.logout(alice.session.token);
  CHECK_FALSE(lab2.authenticate(alice.session.token, 6.0));  // not brought back by its signature
  CHECK(lab1.authenticate(alice.session.token, 6.0));         // the other lab keeps it (docs/web.md, Known limits)
}

TEST_CASE("web: several labs: GET /api/labs answers the directory to a logged-in page, and an empty one without") {
  const auto dir = fresh_temp_dir("labs");
  std::ofstream(dir / "labs.json") << kTwoLabs;
  ServerFixture f([&](ServerSettings& s) {
    s.multi_lab.labs_file = dir / "labs.json";
    s.multi_lab.lab_id = "lab1";
  });
  CHECK(http_call(f.port, http::verb::get, "/api/labs").status == 401);
  const std::string cookie = login_cookie(f.port, "alice", "alice-pw");
  const HttpResult r = http_call(f.port, http::verb::get, "/api/labs", {}, cookie);
  CHECK(r.status == 200);
  CHECK(r.json()["self"] == "lab1");
  CHECK(r.json()["labs"][0]["janus"]["mountpoint"] == 1);
  CHECK(http_call(f.port, http::verb::post, "/api/labs", "{}", cookie).status == 405);

  // A login at this lab is a session at another lab sharing its key, over HTTP as the browser does it.
  std::ofstream(dir / "session.key") << std::string(40, 'k');
  const auto shared_key = [&](ServerSettings& s) { s.multi_lab.session_key_file = dir / "session.key"; };
  ServerFixture one(shared_key), two(shared_key);
  const std::string at_one = login_cookie(one.port, "tess", "tess-pw");
  CHECK(at_one.rfind("labo_session=s1.", 0) == 0);  // signed
  const HttpResult me = http_call(two.port, http::verb::get, "/api/me", {}, at_one);
  CHECK(me.status == 200);
  CHECK(me.json()["user"] == "tess");
  CHECK(http_call(f.port, http::verb::get, "/api/me", {}, at_one).status == 401);  // no shared key there

  ServerFixture alone;
  CHECK(http_call(alone.port, http::verb::get, "/api/labs", {}, login_cookie(alone.port, "bob", "bob-pw")).json()["labs"].empty());
  std::filesystem::remove_all(dir);
}
