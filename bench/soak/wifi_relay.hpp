#pragma once
// A loopback stand-in for the Wi-Fi between the driver and the drone: it relays the AR.Drone 2.0's
// three channels (AT and navdata datagrams, the video's TCP stream) between the driver and the
// emulator, and can cut the link for a while. During a cut every datagram is lost, both ways, and
// the video stream stalls (nothing is read, so the emulator's send times out as it would against a
// drone out of range). The soak cuts the link here, so neither the emulator nor the driver carries a
// switch for it.
//
// The emulator's ports stay the same across an emulator restart; the relay keeps forwarding to them
// and a new video connection from the driver replaces the old pair (the drone serves one client).
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <memory>
#include <thread>

namespace labo::bench {

class WifiRelay {
 public:
  // Forwards to the emulator's ports on 127.0.0.1; listens on free loopback ports of its own.
  WifiRelay(int emulator_at_port, int emulator_navdata_port, int emulator_video_port);
  ~WifiRelay();
  WifiRelay(const WifiRelay&) = delete;
  WifiRelay& operator=(const WifiRelay&) = delete;

  // Where the driver connects.
  int at_port() const;
  int navdata_port() const;
  int video_port() const;

  // Cuts the link from now for `seconds` (a later call extends or shortens the cut).
  void cut_for(double seconds);
  bool cut() const;
  std::uint64_t datagrams_lost() const { return datagrams_lost_; }
  std::uint64_t video_connections() const { return video_connections_; }

 private:
  class Datagrams;
  class VideoStream;
  using Clock = std::chrono::steady_clock;

  boost::asio::io_context io_;
  std::atomic<Clock::rep> cut_until_{0};
  std::atomic<std::uint64_t> datagrams_lost_{0};
  std::atomic<std::uint64_t> video_connections_{0};
  std::unique_ptr<Datagrams> at_, navdata_;
  std::unique_ptr<VideoStream> video_;
  std::thread thread_;
};

}  // namespace labo::bench
