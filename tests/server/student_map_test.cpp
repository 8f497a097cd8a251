// What the student's map and mission progress receive over the WebSocket: the room outline in
// hello, the SLAM map as its own slam_map message (once per revision, to the centimetre, bounded),
// and the stage timeline in every telemetry message.
#include <catch2/catch.hpp>

#include "server/lab/lab_messages.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;

namespace {

std::shared_ptr<const fusion::SlamPointsXy> slam_points(std::uint64_t revision, std::vector<Eigen::Vector2f> xy) {
  auto p = std::make_shared<fusion::SlamPointsXy>();
  p->revision = revision;
  p->map_id = 2;
  p->cell_m = 0.10;
  p->xy_world = std::move(xy);
  return p;
}

// slam_map messages among the next `telemetry_count` telemetry messages.
std::vector<json> slam_maps_during(WsClient& client, int telemetry_count) {
  std::vector<json> maps;
  for (int seen = 0; seen < telemetry_count;) {
    const auto m = client.read();
    REQUIRE(m);
    if (m->binary) continue;
    const json j = m->json();
    if (j["type"] == "slam_map") maps.push_back(j);
    if (j["type"] == "telemetry") ++seen;
  }
  return maps;
}

}  // namespace

TEST_CASE("web: hello carries the room outline and each instrument's facing") {
  ServerFixture f;
  WsClient alice(f.port, login_cookie(f.port, "alice", "alice-pw"));
  const auto hello = alice.wait_for("hello");
  REQUIRE(hello);
  const json& lab = (*hello)["lab"];
  REQUIRE(lab.is_object());
  CHECK(lab["room"]["min"] == json::array({-1.5, -3.0}));
  CHECK(lab["room"]["max"] == json::array({6.5, 3.0}));
  REQUIRE(lab["benches"].size() == 1);
  CHECK(lab["benches"][0]["id"] == "bench_east");
  CHECK(lab["platform"]["id"] == "platform");
  CHECK(lab["base"].contains("yaw"));
  CHECK((*hello)["instruments"][0].contains("facing_rad"));
}

TEST_CASE("web: the SLAM map is sent when its revision changes, to the centimetre, and to a client that joins") {
  ServerFixture f;
  WsClient alice(f.port, login_cookie(f.port, "alice", "alice-pw"));
  REQUIRE(alice.wait_for("hello"));
  CHECK(slam_maps_during(alice, 3).empty());  // no map yet: no slam_map

  f.flight.edit_telemetry([](FlightTelemetry& t) { t.slam_points = slam_points(1, {{1.234f, -0.567f}, {6.0f, 2.5f}}); });
  const auto first = alice.wait_for("slam_map");
  REQUIRE(first);
  CHECK((*first)["revision"] == 1);
  CHECK((*first)["map_id"] == 2);
  CHECK((*first)["cell_m"] == 0.10);
  REQUIRE((*first)["points"].size() == 2);
  CHECK((*first)["points"][0][0].get<double>() == Approx(1.23));
  CHECK((*first)["points"][0][1].get<double>() == Approx(-0.57));
  // The same revision is not sent again with the following telemetry.
  CHECK(slam_maps_during(alice, 5).empty());

  // A client joining now gets the current map right after its hello.
  WsClient bob(f.port, login_cookie(f.port, "bob", "bob-pw"));
  REQUIRE(bob.wait_for("hello"));
  const auto bobs = bob.wait_for("slam_map", 1.0);
  REQUIRE(bobs);
  CHECK((*bobs)["revision"] == 1);

  f.flight.edit_telemetry([](FlightTelemetry& t) { t.slam_points = slam_points(2, {{0.0f, 0.0f}}); });
  const auto second = alice.wait_for("slam_map");
  REQUIRE(second);
  CHECK((*second)["revision"] == 2);
  CHECK((*second)["points"].size() == 1);
}

TEST_CASE("web: a slam_map of the most points the decimation keeps stays small") {
  // 1500 points (TopDownSettings' bound) at the widest coordinates a lab gives: about 24 kB.
  const std::vector<Eigen::Vector2f> widest(fusion::TopDownSettings{}.max_points, Eigen::Vector2f(-12.345f, -12.345f));
  const Message m = slam_map_message(*slam_points(7, widest));
  const json j = json::parse(*m);
  CHECK(j["points"].size() == 1500);
  CHECK(j["points"][0][0].get<double>() == Approx(-12.35).margin(0.006));
  CHECK(m->size() < 28000);
}

TEST_CASE("web: the stage timeline rides in every telemetry message, null before any mission") {
  ServerFixture f;
  WsClient alice(f.port, login_cookie(f.port, "alice", "alice-pw"));
  const auto idle = alice.wait_for("telemetry");
  REQUIRE(idle);
  CHECK((*idle)["timeline"].is_null());

  StageTimeline timeline;
  timeline.observe(10.0, {"inspect", 1, 6, "1 init: taking off", 0, ""});
  timeline.observe(14.0, {"inspect", 2, 6, "2 detect: searching for 'oscilloscope': placed 3/10 detections", 0, ""});
  f.flight.edit_telemetry([&](FlightTelemetry& t) { t.timeline = timeline.timeline(); });
  const auto running = alice.wait_for("telemetry", [](const json& j) { return !j["timeline"].is_null(); });
  REQUIRE(running);
  const json& tl = (*running)["timeline"];
  CHECK(tl["mission"] == "inspect");
  CHECK(tl["stage_count"] == 6);
  CHECK(tl["ended"].is_null());
  REQUIRE(tl["stages"].size() == 2);
  CHECK(tl["stages"][0]["name"] == "init");
  CHECK(tl["stages"][0]["ended"] == 14.0);
  CHECK(tl["stages"][1]["waiting_for"] == "searching for 'oscilloscope': placed 3/10 detections");
  CHECK(tl["stages"][1]["ended"].is_null());
}
