#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "drone/ardrone2/inspect_commands.hpp"
#include "drone/ardrone2/link_receiver.hpp"
#include "drone/replay/replay_link.hpp"
#include "drone/tello/tello_receivers.hpp"

namespace labo::ardrone2 {

using replay::RecordingError;
using replay::RecordingReader;
using replay::ReplayLink;

using namespace ardrone2;

namespace {

struct FrameSink : DroneLinkListener {
  std::filesystem::path dir;
  int width = 0, height = 0;
  std::size_t written = 0;
  std::string write_error;
  void on_navdata(const NavdataSample&) override {}
  void on_link_state(LinkState, Seconds) override {}
  void on_video(const VideoFrame& f) override {
    width = f.bgr.cols;
    height = f.bgr.rows;
    if (dir.empty() || !write_error.empty()) return;
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%06zu.png", written);
    const auto path = dir / name;
    if (!cv::imwrite(path.string(), f.bgr)) {
      write_error = "cannot write " + path.string();
      return;
    }
    ++written;
  }
};

std::uint64_t counter(const LinkStatistics& s, const std::string& kind) {
  const auto it = s.counters.find(kind);
  return it == s.counters.end() ? 0 : it->second;
}

}  // namespace

const CommandSpec& video_command_spec() {
  static const CommandSpec spec{
      "video", "FILE",
      "Demultiplex and decode drone video (a raw capture or a recording); prints a JSON summary.",
      {{"--frames", "DIR", "write each decoded frame as DIR/frame_NNNNNN.png"},
       {"--protocol", "ardrone|tello",
        "a raw capture's format: AR.Drone PaVE from TCP 5555 (default) or a Tello's H.264 from UDP 11111, "
        "the datagrams' bytes one after the other (a recording says which itself)"}},
      1, 1};
  return spec;
}

int run_video_command(const ParsedArgs& args) {
  const std::filesystem::path file = args.positionals.at(0);
  FrameSink sink;
  if (const auto dir = args.value("--frames")) {
    sink.dir = *dir;
    std::error_code ec;
    std::filesystem::create_directories(sink.dir, ec);
    if (ec) {
      std::cerr << "labodrone video: cannot create " << sink.dir.string() << " (" << ec.message() << ")\n";
      return 2;
    }
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::cerr << "labodrone video: " << file.string() << ": cannot read\n";
    return 2;
  }
  const std::string protocol = args.value_or("--protocol", "ardrone");
  if (protocol != "ardrone" && protocol != "tello")
    throw UsageError("--protocol: '" + protocol + "' is not ardrone or tello");
  const bool tello = protocol == "tello";
  Logger quiet("video", LogLevel::Off);
  LinkStatistics stats;
  std::string input_kind;
  try {
    if (RecordingReader::is_recording(file)) {
      input_kind = "recording";
      ReplayLink replay(file, quiet);
      replay.set_listener(&sink);
      replay.run_to_end();
      stats = replay.statistics();
    } else if (tello) {
      input_kind = "udp_capture";
      LinkCounters counters(quiet);
      tello::TelloVideoReceiver receiver(counters, [&sink](const VideoFrame& f) { sink.on_video(f); });
      // Datagram boundaries are not in the file: full-size datagrams, the units ending at the next one.
      std::vector<std::uint8_t> datagram(tello::kTelloVideoDatagramBytes);
      while (in.read(reinterpret_cast<char*>(datagram.data()), static_cast<std::streamsize>(datagram.size())) || in.gcount() > 0) {
        receiver.datagram(std::span(datagram.data(), static_cast<std::size_t>(in.gcount())), 0.0);
      }
      stats = counters.snapshot();
    } else {
      input_kind = "tcp_capture";
      LinkCounters counters(quiet);
      VideoReceiver receiver(counters, [&sink](const VideoFrame& f) { sink.on_video(f); });
      std::vector<std::uint8_t> chunk(64 * 1024);
      while (in.read(reinterpret_cast<char*>(chunk.data()), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
        receiver.bytes(std::span(chunk.data(), static_cast<std::size_t>(in.gcount())), 0.0);
      }
      stats = counters.snapshot();
    }
  } catch (const RecordingError& e) {
    std::cerr << "labodrone video: " << e.what() << "\n";
    return 2;
  }
  nlohmann::json errors = nlohmann::json::object();
  std::uint64_t error_total = 0;
  for (const auto& [kind, n] : stats.counters) {
    const bool is_error = ((kind.starts_with("pave_") || kind.starts_with("tello_video_")) && !kind.ends_with("_bytes")) ||
                          kind == "h264_decode_error";
    if (is_error) {
      errors[kind] = n;
      error_total += n;
    }
  }
  nlohmann::json summary{{"input", input_kind},
                         {"frames", counter(stats, "video_frames")},
                         {"decoded", counter(stats, "video_decoded")},
                         {"keyframes", counter(stats, "video_keyframes")},
                         {"waiting_for_idr", counter(stats, "h264_waiting_for_idr")},
                         {"codec", counter(stats, "pave_not_h264") == 0 ? "h264" : "mixed"},
                         {"width", sink.width},
                         {"height", sink.height},
                         {"errors", error_total},
                         {"errors_by_kind", errors},
                         {"junk_bytes", counter(stats, "pave_junk_bytes") + counter(stats, "tello_video_junk_bytes")}};
  if (!sink.dir.empty()) summary["frames_written"] = sink.written;
  std::cout << summary.dump() << "\n";
  if (!sink.write_error.empty()) {
    std::cerr << "labodrone video: " << sink.write_error << "\n";
    return 2;
  }
  if (counter(stats, "video_frames") == 0) {
    std::cerr << "labodrone video: " << file.string()
              << (input_kind == "udp_capture"   ? ": no H.264 access unit found\n"
                  : input_kind == "tcp_capture" ? ": no PaVE frame found\n"
                                                : ": no video frame in the recording\n");
    return 2;
  }
  if (counter(stats, "video_decoded") == 0) {
    std::cerr << "labodrone video: " << file.string() << ": no frame could be decoded\n";
    return 2;
  }
  return 0;
}

}  // namespace labo::ardrone2
