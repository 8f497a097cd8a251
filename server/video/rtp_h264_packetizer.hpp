#pragma once
// One H.264 access unit (Annex-B, as the drone sent it) cut into RTP packets (RFC 3550 header, RFC
// 6184 payload, packetization-mode 1): a NAL unit that fits the payload budget goes as a single NAL
// unit packet, a larger one as FU-A fragments. Every packet of the unit carries the same 90 kHz
// timestamp, taken from the frame's capture time so that a page can match a decoded frame to the
// overlay geometry of the same frame (rtp_timestamp_of); the last packet carries the marker bit.
// Access unit delimiters and filler data are not sent. No allocation after construction.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace labo::server {

// The 90 kHz RTP timestamp of a frame captured at `capture_unix_ms` (Unix epoch milliseconds, the
// value the overlay geometry carries as `capture_ms`), modulo 2^32. web/janus_view.js computes the
// same from the overlay's `capture_ms`.
std::uint32_t rtp_timestamp_of(double capture_unix_ms);

struct RtpPacketizerOptions {
  std::size_t max_packet_bytes = 1200;  // RTP header included; leaves room for SRTP and the tunnels' headers
  std::uint8_t payload_type = 96;
  std::uint32_t ssrc = 0x4c414230;  // "LAB0"
};

class RtpH264Packetizer {
 public:
  using PacketSink = std::function<void(std::span<const std::uint8_t> packet)>;

  explicit RtpH264Packetizer(RtpPacketizerOptions options = {});

  // Calls `sink` once per packet, in order; the span is valid during the call only. Returns the
  // number of packets (0 when the unit holds no NAL unit to send).
  std::size_t packetize(std::span<const std::uint8_t> annexb, std::uint32_t timestamp, const PacketSink& sink);

  std::uint16_t next_sequence() const { return sequence_; }

 private:
  // One NAL unit (header byte first, no start code); `last` marks the access unit's last NAL unit.
  std::size_t send_nal(std::span<const std::uint8_t> nal, bool last, std::uint32_t timestamp, const PacketSink& sink);
  // Writes the RTP header into packet_ and returns the offset of the payload.
  std::size_t write_header(bool marker, std::uint32_t timestamp);

  RtpPacketizerOptions options_;
  std::uint16_t sequence_ = 0;
  std::vector<std::uint8_t> packet_;
};

// The NAL units of an Annex-B byte stream (start codes of 3 or 4 bytes; trailing zero bytes of a NAL
// unit dropped), in order. Calls `each` with each one's bytes from its header on.
void for_each_nal_unit(std::span<const std::uint8_t> annexb, const std::function<void(std::span<const std::uint8_t>)>& each);

}  // namespace labo::server
