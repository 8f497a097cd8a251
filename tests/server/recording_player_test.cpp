#include <catch2/catch.hpp>

#include <chrono>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <vector>

#include "drone/replay/recording.hpp"
#include "drone/replay/replay_link.hpp"
#include "server/lab/recording_player.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/emulated_recording.hpp"
#include "tests/support/scratch_dir.hpp"

using namespace labo;
using namespace labo::server;
using labo::test::ScratchDir;

namespace {

// What a player sent, from its thread.
struct Received {
  std::mutex mutex;
  std::vector<std::shared_ptr<const std::string>> frames;
  std::vector<ReplayProgress> progress;

  ReplayFrameEncoder::FrameSink frame_sink() {
    return [this](std::shared_ptr<const std::string> w) {
      std::lock_guard lock(mutex);
      frames.push_back(std::move(w));
    };
  }
  RecordingPlayer::ProgressSink progress_sink() {
    return [this](const ReplayProgress& p) {
      std::lock_guard lock(mutex);
      progress.push_back(p);
    };
  }
};

bool wait_for_end(const RecordingPlayer& player, double timeout_s) {
  for (int i = 0; i < timeout_s * 50; ++i) {
    if (player.progress().state != ReplayState::Playing) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace

TEST_CASE("replay: each recorded frame becomes an LDP1 JPEG with the recording's time, the navdata drawn in") {
  const ScratchDir scratch("replay_encoder");
  const auto file = scratch / "flight.ldrec";
  server::test::record_emulated_flight(file, 1.5);

  Received got;
  ReplayFrameEncoder encoder(got.frame_sink(), 320);
  replay::ReplayLink link(file, Logger("test", LogLevel::Off));
  encoder.set_origin(link.next_time());
  link.set_listener(&encoder);
  link.run_to_end();

  REQUIRE(got.frames.size() > 10);
  CHECK(encoder.frames() == got.frames.size());
  CHECK(encoder.navdata() > 10);
  double last_ms = -1;
  for (const auto& wire : got.frames) {
    const auto h = FrameHeader::read(*wire, "LDP1");
    REQUIRE(h);
    CHECK_FALSE(FrameHeader::read(*wire, "LDV1"));  // never taken for the live video
    REQUIRE(h->jpeg_bytes == wire->size() - FrameHeader::kSize);
    CHECK(h->capture_unix_ms >= last_ms);  // the recording's time, from its first record
    CHECK(h->capture_unix_ms < 3000);
    last_ms = h->capture_unix_ms;
  }
  const std::string& last = *got.frames.back();
  const cv::Mat image = cv::imdecode(std::vector<std::uint8_t>(last.begin() + FrameHeader::kSize, last.end()), cv::IMREAD_COLOR);
  REQUIRE_FALSE(image.empty());
  CHECK(image.cols <= 320);  // scaled down to the encoder's width
}

TEST_CASE("replay: a recording plays to its end at its pace times the speed, or stops when asked") {
  const ScratchDir scratch("replay_player");
  const auto file = scratch / "flight.ldrec";
  server::test::record_emulated_flight(file, 1.0);

  SECTION("to the end") {
    Received got;
    RecordingPlayer player(file, 4.0, got.frame_sink(), got.progress_sink(), Logger("test", LogLevel::Off));
    REQUIRE(wait_for_end(player, 10));
    const ReplayProgress end = player.progress();
    CHECK(end.state == ReplayState::Ended);
    CHECK(end.position_s > 0.5);
    std::lock_guard lock(got.mutex);
    CHECK(end.frames == got.frames.size());
    CHECK(got.frames.size() > 5);
    REQUIRE(got.progress.size() >= 2);
    CHECK(got.progress.front().state == ReplayState::Playing);  // announced before its frames
    CHECK(got.progress.back().state == ReplayState::Ended);
  }
  SECTION("stopped") {
    Received got;
    RecordingPlayer player(file, 0.25, got.frame_sink(), got.progress_sink(), Logger("test", LogLevel::Off));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    player.stop();
    REQUIRE(wait_for_end(player, 5));
    CHECK(player.progress().state == ReplayState::Stopped);
    CHECK(player.progress().position_s < 1.0);
  }
}

TEST_CASE("replay: a file that is no recording is refused before anything plays, a corrupt one fails with the reason") {
  const ScratchDir scratch("replay_bad");
  const auto junk = scratch / "junk.ldrec";
  std::ofstream(junk) << "recorded bytes";
  Received got;
  CHECK_THROWS_AS(RecordingPlayer(junk, 1.0, got.frame_sink(), got.progress_sink(), Logger("test", LogLevel::Off)),
                  replay::RecordingError);

  // A valid flight, then a record whose channel is unknown: the player plays the flight, then ends
  // Failed with the reader's reason.
  const auto corrupt = scratch / "corrupt.ldrec";
  server::test::record_emulated_flight(corrupt, 0.5);
  {
    std::ofstream out(corrupt, std::ios::app | std::ios::binary);
    const char bad[] = {static_cast<char>(200), 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    out.write(bad, sizeof bad);
  }
  RecordingPlayer player(corrupt, 8.0, got.frame_sink(), got.progress_sink(), Logger("test", LogLevel::Off));
  REQUIRE(wait_for_end(player, 10));
  const ReplayProgress p = player.progress();
  CHECK(p.state == ReplayState::Failed);
  CHECK_THAT(p.error, Catch::Contains("unknown channel 200"));
  CHECK(p.frames > 0);  // what came before it was played
}
