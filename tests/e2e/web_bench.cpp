// Web benchmark, against a running server (labo_e2e_server or labodrone serve):
//   labo_web_bench PORT SERVER_PID [CLIENTS=20] [SECONDS=20] [STUCK_SECONDS=0] [VIDEO=jpeg|h264|geometry|none] [SLOW_KBPS=0]
// Connects CLIENTS spectators (one session, CLIENTS WebSockets) watching the VIDEO path (geometry: a
// spectator whose video comes from Janus, its frames the overlay messages it gets; none: one whose
// overlays come from Janus too, telemetry and events only), each
// reading everything, and reports per-client frames/s, the bytes each receives per second (video
// and all), the glass-to-client latency (now - the frame's capture time; same machine, same clock)
// and the server's CPU (from /proc/PID/stat) over the run. With SLOW_KBPS (h264), one more viewer
// reads at most SLOW_KBPS kbit/s through a 16 KiB receive buffer, as a slow link would carry it: its
// frames/s, the frames of each rendition it got, the low rendition's bit rate and its latency are
// reported apart. With STUCK_SECONDS it then opens one viewer of the same path that never reads and
// samples the server's resident memory meanwhile.
#include <algorithm>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "server/video/access_unit_wire.hpp"
#include "server/video/frame_header.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;

namespace {

double unix_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double cpu_seconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::string f;
  double utime = 0, stime = 0;
  for (int i = 3; fields >> f; ++i) {
    if (i == 14) utime = std::stod(f);
    if (i == 15) {
      stime = std::stod(f);
      break;
    }
  }
  return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

long rss_kib(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// The capture time of a video message of either path (JPEG frame, H.264 access unit).
std::optional<double> capture_ms(const std::string& message) {
  if (const auto h = FrameHeader::read(message)) return h->capture_unix_ms;
  if (const auto h = AccessUnitHeader::read(message)) return h->capture_unix_ms;
  return std::nullopt;
}

// A viewer on a slow link: reads at most `kbps`, through a small receive buffer.
struct SlowViewerStats {
  int frames = 0;
  int frames_by_rendition[2] = {0, 0};
  double low_bytes = 0, first_low_s = -1, last_low_s = -1, first_low_after_s = -1, all_bytes = 0;
  std::vector<double> latencies;
};

SlowViewerStats run_slow_viewer(unsigned short port, const std::string& cookie, double kbps, double seconds) {
  SlowViewerStats out;
  WsClient ws(port, cookie, {}, 16 * 1024);
  ws.send(std::string(R"({"type":"subscribe","video":"h264","rendition":"auto"})"));
  const auto start = std::chrono::steady_clock::now();
  const auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  double bytes = 0;
  while (since() < seconds) {
    auto m = ws.read(1.0);
    if (!m) break;
    bytes += static_cast<double>(m->data.size());
    out.all_bytes = bytes;
    std::this_thread::sleep_until(start + std::chrono::duration<double>(bytes * 8 / (kbps * 1000)));
    const auto h = m->binary ? AccessUnitHeader::read(m->data) : std::nullopt;
    if (!h) continue;
    ++out.frames;
    ++out.frames_by_rendition[static_cast<int>(h->rendition)];
    out.latencies.push_back(unix_ms() - h->capture_unix_ms);
    if (h->rendition != Rendition::Low) continue;
    if (out.first_low_s < 0) out.first_low_after_s = out.first_low_s = since();
    else out.low_bytes += static_cast<double>(m->data.size());  // from the first low unit's arrival on
    out.last_low_s = since();
  }
  return out;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * (v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: labo_web_bench PORT SERVER_PID [CLIENTS=20] [SECONDS=20] [STUCK_SECONDS=0] [VIDEO=jpeg|h264|geometry|none] [SLOW_KBPS=0]\n";
    return 2;
  }
  const std::string video = argc > 6 ? argv[6] : "jpeg";
  if (video != "jpeg" && video != "h264" && video != "geometry" && video != "none") {
    std::cerr << "labo_web_bench: VIDEO must be jpeg, h264, geometry or none, not '" << video << "'\n";
    return 2;
  }
  const std::string subscribe = R"({"type":"subscribe","video":")" + video + R"("})";
  const bool geometry_only = video == "geometry";
  const auto port = static_cast<unsigned short>(std::stoi(argv[1]));
  const int pid = std::stoi(argv[2]);
  const int clients = argc > 3 ? std::stoi(argv[3]) : 20;
  const double seconds = argc > 4 ? std::stod(argv[4]) : 20;
  const double stuck_seconds = argc > 5 ? std::stod(argv[5]) : 0;
  const double slow_kbps = argc > 7 ? std::stod(argv[7]) : 0;
  if (slow_kbps > 0 && video != "h264") {
    std::cerr << "labo_web_bench: SLOW_KBPS needs the h264 path\n";
    return 2;
  }
  const std::string cookie = login_cookie(port, "student1", "student1-pass");
  if (cookie.empty()) {
    std::cerr << "cannot log in as student1\n";
    return 1;
  }
  std::vector<std::unique_ptr<WsClient>> ws;
  for (int i = 0; i < clients; ++i) {
    ws.push_back(std::make_unique<WsClient>(port, cookie));
    ws.back()->send(subscribe);
  }
  std::mutex mutex;
  std::vector<double> latencies;
  std::vector<double> fps(clients), video_bytes_s(clients), all_bytes_s(clients);
  const double cpu0 = cpu_seconds(pid);
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration<double>(seconds);
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i) {
    threads.emplace_back([&, i] {
      int frames = 0;
      double video_bytes = 0, all_bytes = 0;
      std::vector<double> mine;
      while (std::chrono::steady_clock::now() < deadline) {
        auto m = ws[i]->read(1.0);
        if (!m) break;
        all_bytes += static_cast<double>(m->data.size());
        if (!m->binary) {  // the H.264 path's geometry is part of its video; the geometry path's is all of it
          if (m->data.rfind(R"({"type":"overlay")", 0) != 0) continue;
          video_bytes += static_cast<double>(m->data.size());
          if (!geometry_only) continue;
          const auto overlay = nlohmann::json::parse(m->data, nullptr, false);
          if (!overlay.is_object() || !overlay.contains("capture_ms")) continue;
          ++frames;
          mine.push_back(unix_ms() - overlay["capture_ms"].get<double>());
          continue;
        }
        const auto t = capture_ms(m->data);
        if (!t) continue;
        ++frames;
        video_bytes += static_cast<double>(m->data.size());
        mine.push_back(unix_ms() - *t);
      }
      std::lock_guard lock(mutex);
      fps[i] = frames / seconds;
      video_bytes_s[i] = video_bytes / seconds;
      all_bytes_s[i] = all_bytes / seconds;
      latencies.insert(latencies.end(), mine.begin(), mine.end());
    });
  }
  SlowViewerStats slow;
  if (slow_kbps > 0) threads.emplace_back([&] { slow = run_slow_viewer(port, cookie, slow_kbps, seconds); });
  for (auto& t : threads) t.join();
  if (clients == 0 && slow_kbps <= 0) std::this_thread::sleep_until(deadline);  // the server's CPU with nobody watching
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double server_cores = (cpu_seconds(pid) - cpu0) / wall;
  const auto kbit = [](double bytes_s) { return bytes_s * 8 / 1000; };
  std::cout << "spectators: " << clients << " (" << video << "), " << seconds << " s\n"
            << "frames/s per client: min " << percentile(fps, 0) << ", median " << percentile(fps, 0.5) << "\n"
            << "per client: video " << percentile(video_bytes_s, 0.5) / 1000 << " kB/s (" << kbit(percentile(video_bytes_s, 0.5))
            << " kbit/s), everything " << percentile(all_bytes_s, 0.5) / 1000 << " kB/s (median over clients)\n"
            << "glass-to-client latency ms: median " << percentile(latencies, 0.5) << ", p95 " << percentile(latencies, 0.95)
            << ", max " << percentile(latencies, 1.0) << "\n"
            << "server CPU: " << server_cores << " cores\n";
  if (slow_kbps > 0) {
    const double low_s = slow.last_low_s - slow.first_low_s;
    std::cout << "slow viewer at " << slow_kbps << " kbit/s: " << slow.frames / seconds << " frames/s ("
              << slow.frames_by_rendition[0] << " of the drone's stream, " << slow.frames_by_rendition[1] << " of the low rendition"
              << "); first low unit after " << slow.first_low_after_s << " s; low rendition "
              << (low_s > 0 ? slow.low_bytes * 8 / 1000 / low_s : 0) << " kbit/s (its units and headers, over " << low_s
              << " s); everything it read " << slow.all_bytes * 8 / 1000 / seconds << " kbit/s; latency ms: median " << percentile(slow.latencies, 0.5) << ", p95 " << percentile(slow.latencies, 0.95) << "\n";
  }
  ws.clear();

  if (stuck_seconds > 0) {
    // A viewer that never reads: its socket buffers fill, then the server must drop its frames and
    // finally disconnect it, with memory flat meanwhile.
    const StuckViewer stuck(port, cookie, subscribe);
    const long rss0 = rss_kib(pid);
    long rss_max = rss0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(stuck_seconds);
    while (std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::seconds(1));
      rss_max = std::max(rss_max, rss_kib(pid));
    }
    std::cout << "non-reading viewer for " << stuck_seconds << " s: server RSS " << rss0 / 1024.0 << " MiB at start, max "
              << rss_max / 1024.0 << " MiB, end " << rss_kib(pid) / 1024.0 << " MiB\n";
  }
  return 0;
}
