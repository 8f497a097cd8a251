#include <catch2/catch.hpp>
#include <string>

#include "drone/ardrone2/config_handshake.hpp"

using namespace labo::ardrone2;

TEST_CASE("link: config handshake sends one key at a time and answers the ack with CTRL 5", "[link]") {
  ConfigHandshake h(0.5);
  AtCommandEncoder enc;
  std::string out;
  h.push_back({"general:navdata_demo", "TRUE"});
  h.push_back({"video:video_channel", "1"});

  CHECK_FALSE(h.tick(0.0, false, false, enc, out).sent);  // no navdata yet: wait
  CHECK(out.empty());
  auto r = h.tick(0.03, false, true, enc, out);
  CHECK(r.sent);
  CHECK(out == "AT*CONFIG_IDS=1,\"00000000\",\"00000000\",\"00000000\"\rAT*CONFIG=2,\"general:navdata_demo\",\"TRUE\"\r");
  out.clear();
  r = h.tick(0.06, false, true, enc, out);  // waiting for bit 6
  CHECK(out.empty());
  r = h.tick(0.09, true, true, enc, out);
  REQUIRE(r.acked);
  CHECK(r.acked->key == "general:navdata_demo");
  CHECK(out == "AT*CTRL=3,5,0\r");
  out.clear();
  h.tick(0.12, true, true, enc, out);  // bit still set: CTRL 5 again, nothing new sent
  CHECK(out == "AT*CTRL=4,5,0\r");
  out.clear();
  h.tick(0.15, false, true, enc, out);  // bit cleared: the handshake is over
  CHECK(out.empty());
  r = h.tick(0.18, false, true, enc, out);
  CHECK(r.sent);
  CHECK(out.find("\"video:video_channel\",\"1\"") != std::string::npos);
  out.clear();
  // No acknowledgement: after the timeout the key is reported and sent again.
  CHECK_FALSE(h.tick(0.5, false, true, enc, out).timed_out);
  r = h.tick(0.7, false, true, enc, out);
  REQUIRE(r.timed_out);
  CHECK(*r.timed_out == "video:video_channel");
  CHECK(h.tick(0.73, false, true, enc, out).sent);
  CHECK(h.pending() == 1);
}

TEST_CASE("link: config handshake clears a stale ack before sending", "[link]") {
  ConfigHandshake h;
  AtCommandEncoder enc;
  std::string out;
  h.push_back({"control:altitude_max", "3000"});
  const auto r = h.tick(0.0, true, true, enc, out);
  CHECK_FALSE(r.sent);
  CHECK(out == "AT*CTRL=1,5,0\r");
}
