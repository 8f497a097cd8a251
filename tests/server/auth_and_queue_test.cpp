#include <catch2/catch.hpp>

#include "core/config_reader.hpp"
#include "server/auth/password_hash.hpp"
#include "server/auth/session_store.hpp"
#include "server/lab/control_queue.hpp"
#include "server/server_settings.hpp"

using namespace labo;
using namespace labo::server;

TEST_CASE("web: a PBKDF2 hash verifies its password only, and malformed hashes are refused") {
  const PasswordHash h = PasswordHash::create("s3cret", PasswordHash::kMinIterations);
  const auto parsed = PasswordHash::parse(h.encode());
  REQUIRE(parsed);
  CHECK(parsed->verify("s3cret"));
  CHECK_FALSE(parsed->verify("s3cret "));
  CHECK(PasswordHash::create("s3cret", PasswordHash::kMinIterations).encode() != h.encode());  // salted
  CHECK_FALSE(PasswordHash::parse("plain-text"));
  CHECK_FALSE(PasswordHash::parse("pbkdf2-sha256$100$AAAAAAAAAAAAAAAAAAAAAA==$AAAAAAAAAAAAAAAAAAAAAA=="));  // too few iterations
  CHECK_FALSE(PasswordHash::parse("pbkdf2-sha256$20000$!!!$AAAAAAAAAAAAAAAAAAAAAA=="));
  CHECK_FALSE(PasswordHash::parse("md5$20000$AAAAAAAAAAAAAAAAAAAAAA==$AAAAAAAAAAAAAAAAAAAAAA=="));
}

TEST_CASE("web: sessions log in, expire when idle, and logins are rate limited per address") {
  const UserAccount alice{"alice", Role::Student, PasswordHash::create("pw", PasswordHash::kMinIterations).encode()};
  SessionStore store({alice}, 100.0, 3.0);  // 3 attempts a minute
  const LoginResult ok = store.login("alice", "pw", "10.0.0.1", 0);
  REQUIRE(ok.outcome == LoginOutcome::Ok);
  CHECK(ok.session.token.size() == 64);
  CHECK(store.authenticate(ok.session.token, 50)->user == "alice");
  CHECK(store.authenticate(ok.session.token, 149));  // seen at 50: idle 99 s
  CHECK_FALSE(store.authenticate(ok.session.token, 300));
  CHECK(store.login("alice", "wrong", "10.0.0.1", 1).outcome == LoginOutcome::BadCredentials);
  CHECK(store.login("nobody", "pw", "10.0.0.1", 1).outcome == LoginOutcome::BadCredentials);
  CHECK(store.login("alice", "pw", "10.0.0.1", 1).outcome == LoginOutcome::RateLimited);
  CHECK(store.login("alice", "pw", "10.0.0.2", 1).outcome == LoginOutcome::Ok);
}

TEST_CASE("web: the control queue grants in order, warns, ends turns and lets a teacher take over") {
  ControlRules rules;
  rules.time_limit_s = 100;
  rules.warnings_s = {30, 10};
  rules.heartbeat_timeout_s = 5;
  ControlQueue q(rules);
  const Participant a{1, "alice", Role::Student}, b{2, "bob", Role::Student}, t{3, "tess", Role::Teacher};
  auto n = q.request(a, 0);
  REQUIRE(n.size() == 1);
  CHECK(n[0].kind == ControlNotice::Kind::Granted);
  CHECK(q.request(b, 0).empty());
  CHECK(*q.queue_position(2) == 1);
  for (double s = 1; s <= 69; s += 1) q.heartbeat(1, s), q.tick(s);
  q.heartbeat(1, 70);
  n = q.tick(70.5);
  REQUIRE(n.size() == 1);
  CHECK(n[0].kind == ControlNotice::Kind::Warning);
  for (double s = 71; s <= 99; s += 1) q.heartbeat(1, s), q.tick(s);
  n = q.tick(100.5);  // time limit: bob's turn
  REQUIRE(n.size() == 2);
  CHECK(n[0].kind == ControlNotice::Kind::Ended);
  CHECK(n[0].reason == "time limit");
  CHECK(n[1].kind == ControlNotice::Kind::Granted);
  CHECK(q.is_controller(2));
  // Bob stops sending heartbeats.
  n = q.tick(106);
  REQUIRE(n.size() == 1);
  CHECK(n[0].reason == "heartbeat lost");
  CHECK_FALSE(q.snapshot(106).controller);
  // A student cannot take over; a teacher can, and the student waits first in line.
  q.request(a, 107);
  CHECK(q.take_over(b, 108).empty());
  n = q.take_over(t, 108);
  CHECK(q.is_controller(3));
  CHECK(*q.queue_position(1) == 1);
  CHECK(q.snapshot(108).remaining_s == -1);  // no limit for a teacher
  // The teacher leaves: alice gets control back.
  n = q.leave(3, 109);
  REQUIRE(n.size() == 1);
  CHECK(q.is_controller(1));
}

TEST_CASE("web: server settings refuse bad users, roles and limits with the key path") {
  const auto read = [](const std::string& text) {
    const ConfigDocument doc = ConfigDocument::parse(text, "test.json");
    return read_server_settings(doc.root(), ".");
  };
  const std::string hash = PasswordHash::create("x", PasswordHash::kMinIterations).encode();
  CHECK(read(R"({"users": [{"name": "a", "role": "student", "password_hash": ")" + hash + R"("}]})").users.size() == 1);
  CHECK_THROWS_WITH(read(R"({"users": [{"name": "a", "role": "pilot", "password_hash": ")" + hash + R"("}]})"),
                    Catch::Contains("role"));
  CHECK_THROWS_WITH(read(R"({"users": [{"name": "a", "role": "student", "password_hash": "secret"}]})"),
                    Catch::Contains("password_hash"));
  CHECK_THROWS_WITH(read(R"({"users": [{"name": "a", "role": "student", "password_hash": ")" + hash + R"("},
                                       {"name": "a", "role": "admin", "password_hash": ")" + hash + R"("}]})"),
                    Catch::Contains("twice"));
  CHECK_THROWS_WITH(read(R"({"control": {"time_limit_s": 60, "warnings_s": [90]}})"), Catch::Contains("warnings_s"));
  CHECK_THROWS_WITH(read(R"({"clients": {"queue": 3}})"), Catch::Contains("queue"));
}
