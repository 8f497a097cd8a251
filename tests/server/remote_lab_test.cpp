#include <catch2/catch.hpp>
#include <atomic>
#include <future>
#include <mutex>
#include <thread>

#include "drone/replay/recording.hpp"
#include "server/lab/remote_lab.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/emulated_recording.hpp"
#include "tests/support/scratch_dir.hpp"
#include "tests/server/support/scripted_flight.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;

namespace {

// A client without a socket: it records what it is sent. Like a WebSocket session, it leaves the lab
// from its destructor.
class RecordingClient final : public LabClient {
 public:
  RecordingClient(ClientId id, std::string user, RemoteLab& lab) : id_(id), lab_(lab) { session_.user = std::move(user); }
  ~RecordingClient() override { lab_.leave(id_); }
  ClientId id() const override { return id_; }
  const SessionInfo& session() const override { return session_; }
  void send_event(std::shared_ptr<const std::string> json) override {
    std::lock_guard lock(mutex);
    events.push_back(*json);
    if (on_send) on_send();
  }
  void send_frame(std::shared_ptr<const std::string>) override { ++frames; }
  void send_access_unit(const WireAccessUnit&) override { ++units; }
  void send_reading_view(std::shared_ptr<const std::string>) override {}
  void send_replay_frame(std::shared_ptr<const std::string> wire) override {
    std::lock_guard lock(mutex);
    last_replay_frame = std::move(wire);
    ++replay_frames;
  }
  void select_video(VideoPath path, RenditionChoice) override { video = path; }
  void disconnect(const std::string&) override {}

  std::mutex mutex;  // events and the replay's frame: a replay sends from its own thread
  std::vector<std::string> events;
  std::atomic<int> replay_frames{0};
  std::shared_ptr<const std::string> last_replay_frame;
  int frames = 0, units = 0;
  VideoPath video = VideoPath::Jpeg;
  std::function<void()> on_send;

 private:
  ClientId id_;
  SessionInfo session_;
  RemoteLab& lab_;
};

struct LabFixture {
  ScriptedFlight flight;
  ServerSettings settings;
  ServerMetrics metrics;
  SteadyClock clock;
  AuditLog audit{{}};
  RemoteLab lab{flight, settings, metrics, clock, audit, Logger("test", LogLevel::Warn)};

  std::shared_ptr<RecordingClient> join(ClientId id, const std::string& user) {
    auto client = std::make_shared<RecordingClient>(id, user, lab);
    lab.join(client);
    return client;
  }
};

}  // namespace

TEST_CASE("lab: a client whose last owner is a delivery leaves without a deadlock") {
  LabFixture f;
  auto keeper = f.join(1, "alice");
  auto closing = f.join(2, "bob");
  // Bob's session closes while the new control state is being delivered to him: the delivery's
  // reference is then his last, and his destructor leaves the lab (a WebSocket session closed on
  // another io thread meanwhile).
  std::weak_ptr<RecordingClient> watch = closing;
  closing->on_send = [&closing] { closing.reset(); };
  auto done = std::async(std::launch::async, [&] { f.lab.on_message(*keeper, R"({"type":"request_control"})"); });
  REQUIRE(done.wait_for(std::chrono::seconds(5)) == std::future_status::ready);
  CHECK(watch.expired());
  CHECK(f.lab.client_count() == 1);
  CHECK(f.lab.control_state_json().find("\"spectators\":1") != std::string::npos);
}

TEST_CASE("lab: control states carry a growing sequence number, messages are serialised once for all") {
  LabFixture f;
  auto a = f.join(1, "alice");
  auto b = f.join(2, "bob");
  f.lab.on_message(*a, R"({"type":"request_control"})");
  std::vector<std::uint64_t> seqs;
  for (const std::string& e : b->events)
    if (const auto at = e.find("\"seq\":"); at != std::string::npos) seqs.push_back(std::stoull(e.substr(at + 6)));
  REQUIRE(seqs.size() == 2);  // bob's join, alice's request
  CHECK(seqs[0] < seqs[1]);
  CHECK(a->events.back().find("\"controlling\":true") != std::string::npos);
  f.flight.publish_frame(3);
  CHECK(a->frames == 1);
  CHECK(b->frames == 1);
}

namespace {

bool replay_over(RemoteLab& lab, double timeout_s) {
  for (int i = 0; i < timeout_s * 50; ++i) {
    const auto s = lab.replays().status();
    if (s && s->progress.state != ReplayState::Playing) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

int replay_events(RecordingClient& c) {
  std::lock_guard lock(c.mutex);
  int n = 0;
  for (const std::string& e : c.events) n += e.find(R"("type":"replay")") != std::string::npos;
  return n;
}

}  // namespace

TEST_CASE("lab: a replay goes to the connections of the admin who asked, or to everyone, never to the live video") {
  const labo::test::ScratchDir scratch("replay_audience");
  const auto file = scratch / "flight.ldrec";
  record_emulated_flight(file, 1.0);
  LabFixture f;
  auto root_page = f.join(1, "root");
  auto root_admin_page = f.join(2, "root");
  auto alice = f.join(3, "alice");

  REQUIRE(f.lab.replays().start("root", "flight.ldrec", file, ReplayAudience::Requester, 4.0).status == 200);
  REQUIRE(replay_over(f.lab, 10));
  CHECK(f.lab.replays().status()->progress.state == ReplayState::Ended);
  CHECK(root_page->replay_frames > 5);
  CHECK(root_admin_page->replay_frames == root_page->replay_frames.load());
  CHECK(replay_events(*root_page) >= 2);  // playing, then ended
  CHECK(alice->replay_frames == 0);
  CHECK(replay_events(*alice) == 0);
  CHECK(root_page->frames == 0);  // the live video's slot is not used
  {
    std::lock_guard lock(root_page->mutex);
    REQUIRE(root_page->last_replay_frame);
    CHECK(FrameHeader::read(*root_page->last_replay_frame, "LDP1"));
  }

  REQUIRE(f.lab.replays().start("root", "flight.ldrec", file, ReplayAudience::Everyone, 4.0).status == 200);
  REQUIRE(replay_over(f.lab, 10));
  CHECK(alice->replay_frames > 5);
  CHECK(replay_events(*alice) >= 2);
}

TEST_CASE("lab: one replay at a time, a second refused while the first plays, a stop ends it") {
  const labo::test::ScratchDir scratch("replay_one");
  const auto file = scratch / "long.ldrec";
  {
    replay::RecordingWriter w(file);  // 60 s of notes: plays until stopped
    w.note(0.0, "start");
    w.note(60.0, "end");
  }
  LabFixture f;
  auto root = f.join(1, "root");
  CHECK(f.lab.replays().stop("root").status == 404);
  REQUIRE(f.lab.replays().start("root", "long.ldrec", file, ReplayAudience::Requester, 1.0).status == 200);
  const ReplayOutcome second = f.lab.replays().start("admin2", "long.ldrec", file, ReplayAudience::Everyone, 1.0);
  CHECK(second.status == 409);
  CHECK_THAT(second.message, Catch::Contains("long.ldrec") && Catch::Contains("root"));
  CHECK(f.lab.replays().stop("root").status == 200);
  REQUIRE(replay_over(f.lab, 5));
  CHECK(f.lab.replays().status()->progress.state == ReplayState::Stopped);
  CHECK(f.lab.replays().start("admin2", "long.ldrec", file, ReplayAudience::Everyone, 1.0).status == 200);
}
