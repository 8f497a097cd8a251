#include "server/video/rtp_video_forwarder.hpp"

#include "server/video/access_unit_wire.hpp"

namespace labo::server {

RtpVideoForwarder::RtpVideoForwarder(const UdpTarget& target, RtpPacketizerOptions options)
    : sender_(target), packetizer_(options) {}

void RtpVideoForwarder::forward(const WireAccessUnit& unit) {
  if (!unit.wire || unit.wire->size() < AccessUnitHeader::kSize) return;
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(unit.wire->data());
  const std::span<const std::uint8_t> annexb(bytes + AccessUnitHeader::kSize, unit.wire->size() - AccessUnitHeader::kSize);
  units_++;
  packetizer_.packetize(annexb, rtp_timestamp_of(unit.capture_unix_ms),
                        [this](std::span<const std::uint8_t> packet) { sender_.send(packet); });
}

RtpForwarderCounters RtpVideoForwarder::counters() const {
  const UdpCounters c = sender_.counters();
  return {units_.load(), c.datagrams, c.bytes, c.dropped};
}

}  // namespace labo::server
