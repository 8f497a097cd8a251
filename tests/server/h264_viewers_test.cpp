#include <catch2/catch.hpp>
#include <thread>

#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::test;
using nlohmann::json;

namespace {

// The next video message (overlay geometry, access unit or JPEG frame) as "overlay N", "unit N key"
// / "unit N", "jpeg N"; other JSON (telemetry, control) is skipped. "none" after a timeout (the
// client is unusable after one).
std::string next_video(WsClient& c, double timeout_s = 3.0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto m = c.read(std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
    if (!m) break;
    if (!m->binary) {
      const json j = m->json();
      if (j.value("type", "") == "overlay") return "overlay " + std::to_string(j["frame"].get<int>());
      continue;
    }
    if (const auto h = AccessUnitHeader::read(m->data))
      return "unit " + std::to_string(h->frame_number) + (h->keyframe ? " key" : "");
    if (const auto h = FrameHeader::read(m->data)) return "jpeg " + std::to_string(h->frame_number);
    return "unknown binary";
  }
  return "none";
}

}  // namespace

TEST_CASE("web: H.264 viewers get the access units from an IDR on with their geometry, JPEG viewers the frames") {
  ServerFixture f;
  WsClient h264(f.port, login_cookie(f.port, "alice", "alice-pw"));
  WsClient jpeg(f.port, login_cookie(f.port, "bob", "bob-pw"));
  REQUIRE(jpeg.wait_for("hello"));
  h264.send(json{{"type", "subscribe"}, {"video", "h264"}});
  const auto subscribed = h264.wait_for("subscribed");
  REQUIRE(subscribed);
  CHECK((*subscribed)["video"] == "h264");

  f.flight.publish_access_unit(1, false);  // before any IDR: useless to a decoder, not sent
  f.flight.publish_access_unit(2, true);
  f.flight.publish_access_unit(3, false);
  f.flight.publish_frame(7);
  CHECK(next_video(h264) == "overlay 2");
  CHECK(next_video(h264) == "unit 2 key");
  CHECK(next_video(h264) == "overlay 3");
  CHECK(next_video(h264) == "unit 3");
  CHECK(next_video(jpeg) == "jpeg 7");
  f.flight.publish_access_unit(4, false);
  CHECK(next_video(h264) == "overlay 4");  // not frame 7: no JPEG for the H.264 viewer
  CHECK(next_video(h264) == "unit 4");
  CHECK(f.server->metrics().ws_units_skipped.load() == 1);

  // Back to JPEG: frames again, units no more.
  h264.send(json{{"type", "subscribe"}, {"video", "jpeg"}});
  REQUIRE(h264.wait_for("subscribed"));
  f.flight.publish_access_unit(5, true);
  f.flight.publish_frame(8);
  CHECK(next_video(h264) == "jpeg 8");
}

TEST_CASE("web: an H.264 viewer that reads nothing is cut off with its queue bounded, the other keeps its video") {
  ServerFixture f([](ServerSettings& s) {
    s.clients.video_queue_frames = 4;
    s.clients.write_timeout_s = 2.0;
  });
  const StuckViewer stuck(f.port, login_cookie(f.port, "bob", "bob-pw"), R"({"type":"subscribe","video":"h264"})");

  WsClient good(f.port, login_cookie(f.port, "alice", "alice-pw"));
  good.send(json{{"type", "subscribe"}, {"video", "h264"}});
  REQUIRE(good.wait_for("subscribed"));
  int received = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::uint32_t i = 0; std::chrono::steady_clock::now() - start < std::chrono::seconds(4); ++i) {
    f.flight.publish_access_unit(i, i % 15 == 0, 30000);  // 30 kB units: the stuck socket fills at once
    for (int m = 0; m < 2; ++m) received += next_video(good, 1.0).rfind("unit", 0) == 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  CHECK(received > 100);
  CHECK(f.server->metrics().ws_slow_disconnects.load() == 1);
  CHECK(f.server->metrics().ws_keyframe_waits.load() >= 1);
  CHECK(f.server->metrics().ws_clients.load() == 1);
  // Memory: the shared unit buffers stayed at what the queues bound (the pool starts with 32).
  CHECK(f.flight.access_unit_buffers() <= 40);
}
