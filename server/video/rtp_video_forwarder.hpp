#pragma once
// The drone's H.264 stream forwarded as RTP over UDP to a media server (a Janus streaming mount
// point; scripts/janus/): each access unit as it came from the drone, not decoded or re-encoded,
// packetized by RtpH264Packetizer with its capture time as the 90 kHz timestamp. The socket is
// non-blocking: a datagram the kernel cannot take at once is dropped and counted, so the link's
// thread that calls forward() never waits on the media server. No allocation per unit.
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "server/lab/flight_service.hpp"
#include "server/video/rtp_h264_packetizer.hpp"

namespace labo {

struct RtpTarget {
  std::string host = "127.0.0.1";
  unsigned short port = 0;
};

// "HOST:PORT" (an IPv4 or IPv6 literal, IPv6 in brackets) or nullopt; `error` says what was wrong.
std::optional<RtpTarget> parse_rtp_target(const std::string& text, std::string& error);

struct RtpForwarderCounters {
  std::uint64_t units = 0, packets = 0, bytes = 0, packets_dropped = 0;
};

class RtpVideoForwarder {
 public:
  // Throws std::runtime_error naming the target when the address does not resolve to an IP literal.
  explicit RtpVideoForwarder(const RtpTarget& target, RtpPacketizerOptions options = {});

  // One access unit of the H.264 path (its LDH1 header is skipped). Called from one thread at a time.
  void forward(const WireAccessUnit& unit);
  RtpForwarderCounters counters() const;
  const RtpTarget& target() const { return target_; }

 private:
  RtpTarget target_;
  boost::asio::io_context io_;  // the socket's; never run (sends are synchronous and non-blocking)
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint endpoint_;
  RtpH264Packetizer packetizer_;
  std::atomic<std::uint64_t> units_{0}, packets_{0}, bytes_{0}, dropped_{0};
};

}  // namespace labo
