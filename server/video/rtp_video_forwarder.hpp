#pragma once
// The drone's H.264 stream forwarded as RTP over UDP to a media server (a Janus streaming mount
// point; scripts/janus/): each access unit as it came from the drone, not decoded or re-encoded,
// packetized by RtpH264Packetizer with its capture time as the 90 kHz timestamp. Sent by a
// UdpSender: a datagram the kernel cannot take at once is dropped and counted, so the link's thread
// that calls forward() never waits on the media server. No allocation per unit.
#include <atomic>
#include <cstdint>

#include "server/lab/flight_service.hpp"
#include "server/video/rtp_h264_packetizer.hpp"
#include "server/video/udp_sender.hpp"

namespace labo::server {

struct RtpForwarderCounters {
  std::uint64_t units = 0, packets = 0, bytes = 0, packets_dropped = 0;
};

class RtpVideoForwarder {
 public:
  // Throws std::runtime_error naming the target when its host is not an IP literal.
  explicit RtpVideoForwarder(const UdpTarget& target, RtpPacketizerOptions options = {});

  // One access unit of the H.264 path (its LDH1 header is skipped). Called from one thread at a time.
  void forward(const WireAccessUnit& unit);
  RtpForwarderCounters counters() const;
  const UdpTarget& target() const { return sender_.target(); }

 private:
  UdpSender sender_;
  RtpH264Packetizer packetizer_;
  std::atomic<std::uint64_t> units_{0};
};

}  // namespace labo::server
