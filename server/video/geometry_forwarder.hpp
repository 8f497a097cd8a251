#pragma once
// Each frame's overlay geometry sent once, as UDP datagrams (GeometryDatagrams), to the media
// server's data port: a Janus mount point relays every datagram to each viewer's data channel, so
// the geometry costs LaboDrone the same for one viewer or five hundred (docs/web.md "Many viewers and
// several labs"). Never blocks (UdpSender). Called from one thread at a time.
#include <atomic>
#include <cstdint>
#include <string_view>

#include "server/video/geometry_datagrams.hpp"
#include "server/video/udp_sender.hpp"

namespace labo::server {

struct GeometryForwarderCounters {
  std::uint64_t frames = 0, datagrams = 0, bytes = 0, dropped = 0;
};

class GeometryForwarder {
 public:
  explicit GeometryForwarder(const UdpTarget& target) : sender_(target) {}

  void forward(std::uint32_t frame, std::string_view geometry) {
    frames_++;
    datagrams_.split(frame, geometry, [this](std::span<const char> datagram) { sender_.send(datagram); });
  }
  GeometryForwarderCounters counters() const {
    const UdpCounters c = sender_.counters();
    return {frames_.load(), c.datagrams, c.bytes, c.dropped};
  }
  const UdpTarget& target() const { return sender_.target(); }

 private:
  UdpSender sender_;
  GeometryDatagrams datagrams_;
  std::atomic<std::uint64_t> frames_{0};
};

}  // namespace labo::server
