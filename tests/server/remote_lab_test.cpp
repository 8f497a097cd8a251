#include <catch2/catch.hpp>
#include <future>

#include "server/lab/remote_lab.hpp"
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
    events.push_back(*json);
    if (on_send) on_send();
  }
  void send_frame(std::shared_ptr<const std::string>) override { ++frames; }
  void send_access_unit(const WireAccessUnit&) override { ++units; }
  void send_reading_view(std::shared_ptr<const std::string>) override {}
  void select_video(VideoPath path, RenditionChoice) override { video = path; }
  void disconnect(const std::string&) override {}

  std::vector<std::string> events;
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
