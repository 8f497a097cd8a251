#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
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

namespace {

// A viewer's messages as the test's reader thread saw them.
struct Seen {
  std::mutex mutex;
  std::vector<Rendition> units;  // the rendition of each access unit received, in order
  std::vector<json> renditions;  // the "rendition" messages
  bool keyframe_first = true;    // the first unit of each rendition was an IDR
};

// Reads everything `c` receives until `stop`, at most `bytes_per_s` (0: as fast as it comes); after
// `units_before_send` access units it sends `then_send` (from this thread: the client is not shared).
std::thread reader(WsClient& c, Seen& seen, std::atomic<bool>& stop, double bytes_per_s,
                   std::size_t units_before_send = 0, json then_send = nullptr) {
  return std::thread([&c, &seen, &stop, bytes_per_s, units_before_send, then_send] {
    const auto start = std::chrono::steady_clock::now();
    double bytes = 0;
    while (!stop) {
      const auto m = c.read(1.0);
      if (!m) break;  // the stream ended (a client is unusable after a timeout)
      if (!then_send.is_null() && seen.units.size() == units_before_send) c.send(then_send);
      bytes += static_cast<double>(m->data.size());
      std::lock_guard lock(seen.mutex);
      if (!m->binary) {
        const json j = m->json();
        if (j.value("type", "") == "rendition") seen.renditions.push_back(j);
      } else if (const auto h = AccessUnitHeader::read(m->data)) {
        if ((seen.units.empty() || seen.units.back() != h->rendition) && !h->keyframe) seen.keyframe_first = false;
        seen.units.push_back(h->rendition);
      }
      if (bytes_per_s > 0) std::this_thread::sleep_until(start + std::chrono::duration<double>(bytes / bytes_per_s));
    }
  });
}

// The runtime's side for `seconds` at 30 frames/s: the drone's units (`source_bytes` each, an IDR every
// 15), and, while a viewer needs it, the low rendition's (a tenth of the size, an IDR when asked).
void publish_both(ScriptedFlight& flight, double seconds, std::size_t source_bytes, std::uint32_t& n, int* low_units = nullptr) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  auto next = std::chrono::steady_clock::now();
  for (; std::chrono::steady_clock::now() < end; ++n) {
    flight.publish_access_unit(n, n % 15 == 0, source_bytes);
    if (flight.low_rendition_wanted()) {
      flight.publish_access_unit(n, flight.take_low_keyframe_request() || n % 30 == 0, source_bytes / 10, Rendition::Low);
      if (low_units) ++*low_units;
    }
    next += std::chrono::milliseconds(33);
    std::this_thread::sleep_until(next);
  }
}

}  // namespace

TEST_CASE("web: an H.264 viewer whose link cannot carry the drone's stream moves to the shared low rendition, the others stay") {
  ServerFixture f([](ServerSettings& s) {
    s.clients.rendition_max_lag_s = 0.3;
    s.clients.rendition_probe_after_s = 600;  // no probe during the test
  });
  WsClient fast(f.port, login_cookie(f.port, "alice", "alice-pw"));
  WsClient slow(f.port, login_cookie(f.port, "bob", "bob-pw"), {}, 16 * 1024);
  for (WsClient* c : {&fast, &slow}) {
    c->send(json{{"type", "subscribe"}, {"video", "h264"}});
    REQUIRE(c->wait_for("subscribed"));
  }
  CHECK_FALSE(f.flight.low_rendition_wanted());  // nobody needs it yet: no encoder would run
  Seen fast_seen, slow_seen;
  std::atomic<bool> stop{false};
  std::thread fast_reader = reader(fast, fast_seen, stop, 0);
  std::thread slow_reader = reader(slow, slow_seen, stop, 100000);  // 800 kbit/s under a 2.4 Mbit/s stream
  std::uint32_t n = 0;
  int low_units = 0;
  publish_both(f.flight, 8.0, 10000, n, &low_units);
  stop = true;
  fast_reader.join();
  slow_reader.join();

  CHECK(low_units > 100);  // encoded once for the slow viewer, not per viewer
  CHECK(f.server->metrics().low_rendition_viewers.load() == 1);
  CHECK(f.server->metrics().ws_rendition_changes.load() == 1);
  {
    const auto low = std::find_if(slow_seen.renditions.begin(), slow_seen.renditions.end(),
                                  [](const json& j) { return j["rendition"] == "low"; });
    REQUIRE(low != slow_seen.renditions.end());
    CHECK((*low)["choice"] == "auto");
    CHECK((*low)["reason"].get<std::string>().find("kbit/s") != std::string::npos);
    CHECK((*low)["throughput_kbps"].get<double>() < 1000);
  }
  REQUIRE_FALSE(slow_seen.units.empty());
  CHECK(slow_seen.units.back() == Rendition::Low);
  CHECK(slow_seen.keyframe_first);  // each rendition started at an IDR
  CHECK(fast_seen.units.size() > 150);
  CHECK(std::count(fast_seen.units.begin(), fast_seen.units.end(), Rendition::Low) == 0);
  CHECK(fast_seen.renditions.back()["rendition"] == "source");

  slow.send(json{{"type", "subscribe"}, {"video", "jpeg"}});  // off the H.264 path: the encoder may stop
  for (int i = 0; i < 100 && f.flight.low_rendition_wanted(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  CHECK_FALSE(f.flight.low_rendition_wanted());
}

TEST_CASE("web: a viewer that asks for the low rendition gets it from an IDR at once, and the drone's stream back at its next IDR") {
  ServerFixture f;
  WsClient c(f.port, login_cookie(f.port, "alice", "alice-pw"));
  c.send(json{{"type", "subscribe"}, {"video", "h264"}, {"rendition", "low"}});
  REQUIRE(c.wait_for("subscribed"));
  const auto told = c.wait_for("rendition");
  REQUIRE(told);
  CHECK((*told)["rendition"] == "low");
  CHECK((*told)["choice"] == "low");
  CHECK(f.flight.low_rendition_wanted());
  CHECK(f.flight.take_low_keyframe_request());  // a new low viewer gets an IDR at the next frame
  CHECK_FALSE(f.flight.take_low_keyframe_request());

  Seen seen;
  std::atomic<bool> stop{false};
  std::thread t = reader(c, seen, stop, 0, 30, json{{"type", "subscribe"}, {"video", "h264"}, {"rendition", "auto"}});
  std::uint32_t n = 0;  // an IDR of both renditions first
  publish_both(f.flight, 2.5, 3000, n);
  stop = true;
  t.join();
  REQUIRE(seen.units.size() > 60);
  CHECK(seen.units.front() == Rendition::Low);
  CHECK(seen.units[29] == Rendition::Low);
  CHECK(seen.units.back() == Rendition::Source);
  CHECK(seen.keyframe_first);
  CHECK_FALSE(f.flight.low_rendition_wanted());
}
