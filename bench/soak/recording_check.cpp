#include "bench/soak/recording_check.hpp"

#include "drone/replay/recording.hpp"
#include "drone/replay/replay_link.hpp"

namespace labo::bench {

using replay::Record;
using replay::RecordingReader;
using replay::ReplayLink;

namespace {

constexpr std::uint64_t kSignatureBytes = 12, kRecordHeaderBytes = 16;

struct CountingListener final : DroneLinkListener {
  std::uint64_t navdata = 0, frames = 0;
  void on_navdata(const NavdataSample&) override { ++navdata; }
  void on_video(const VideoFrame&) override { ++frames; }
  void on_link_state(LinkState, Seconds) override {}
};

}  // namespace

RecordingCheck check_recording(const std::filesystem::path& file) {
  RecordingCheck c;
  std::error_code ec;
  c.file_bytes = std::filesystem::file_size(file, ec);
  if (ec) {
    c.error = file.string() + ": " + ec.message();
    return c;
  }
  try {
    // Every record, and nothing after the last: the sizes read add up to the file's.
    RecordingReader reader(file);
    Record record;
    c.record_bytes = kSignatureBytes;
    while (reader.next(record)) {
      ++c.records;
      c.record_bytes += kRecordHeaderBytes + record.bytes.size();
    }
    if (reader.truncated()) {
      c.error = "the last record is cut short";
      return c;
    }
    if (c.record_bytes != c.file_bytes) {
      c.error = "records add up to " + std::to_string(c.record_bytes) + " bytes of " + std::to_string(c.file_bytes);
      return c;
    }
    ReplayLink replay(file, Logger("replay", LogLevel::Off));
    CountingListener counts;
    replay.set_listener(&counts);
    replay.run_to_end();
    c.navdata = counts.navdata;
    c.frames = counts.frames;
    c.read_to_end = !replay.truncated() && c.navdata > 0 && c.frames > 0;
    if (!c.read_to_end) c.error = "the replay delivered no navdata or no frame";
  } catch (const std::exception& e) {
    c.error = e.what();
  }
  return c;
}

}  // namespace labo::bench
