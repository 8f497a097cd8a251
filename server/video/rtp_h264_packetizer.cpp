#include "server/video/rtp_h264_packetizer.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace labo::server {
namespace {

constexpr std::size_t kRtpHeaderBytes = 12;
constexpr std::uint8_t kNalTypeMask = 0x1f;
constexpr std::uint8_t kNalAccessUnitDelimiter = 9;
constexpr std::uint8_t kNalFillerData = 12;
constexpr std::uint8_t kFuA = 28;

bool worth_sending(std::span<const std::uint8_t> nal) {
  if (nal.empty()) return false;
  const std::uint8_t type = nal[0] & kNalTypeMask;
  return type != kNalAccessUnitDelimiter && type != kNalFillerData;
}

// Where the start code at or after `from` ends (the NAL unit's first byte), or npos.
std::size_t after_start_code(std::span<const std::uint8_t> s, std::size_t from) {
  for (std::size_t i = from; i + 2 < s.size(); ++i)
    if (s[i] == 0 && s[i + 1] == 0 && s[i + 2] == 1) return i + 3;
  return std::dynamic_extent;
}

}  // namespace

std::uint32_t rtp_timestamp_of(double capture_unix_ms) {
  // 90 ticks per millisecond; Unix milliseconds times 90 stays below 2^53, so the product is exact
  // enough for the page to compute the same value from the JSON's capture_ms.
  const auto ticks = static_cast<std::uint64_t>(std::llround(capture_unix_ms * 90.0));
  return static_cast<std::uint32_t>(ticks & 0xffffffffu);
}

void for_each_nal_unit(std::span<const std::uint8_t> annexb, const std::function<void(std::span<const std::uint8_t>)>& each) {
  constexpr std::size_t npos = std::dynamic_extent;
  std::size_t begin = after_start_code(annexb, 0);
  while (begin != npos && begin < annexb.size()) {
    const std::size_t next = after_start_code(annexb, begin);
    std::size_t end = next == npos ? annexb.size() : next - 3;
    while (end > begin && annexb[end - 1] == 0) --end;  // a 4-byte start code's zero, trailing_zero_8bits
    if (end > begin) each(annexb.subspan(begin, end - begin));
    begin = next;
  }
}

RtpH264Packetizer::RtpH264Packetizer(RtpPacketizerOptions options) : options_(options) {
  if (options_.max_packet_bytes < kRtpHeaderBytes + 3 || options_.max_packet_bytes > 65507)
    throw std::invalid_argument("RTP packet size " + std::to_string(options_.max_packet_bytes) +
                                " bytes: expected 15 to 65507 (header, FU-A headers and at least one byte)");
  if (options_.payload_type > 127)
    throw std::invalid_argument("RTP payload type " + std::to_string(options_.payload_type) + ": expected 0 to 127");
  packet_.resize(options_.max_packet_bytes);
}

std::size_t RtpH264Packetizer::packetize(std::span<const std::uint8_t> annexb, std::uint32_t timestamp,
                                         const PacketSink& sink) {
  // One NAL unit held back: the marker bit goes on the last one sent, which is known only at the end.
  std::optional<std::span<const std::uint8_t>> pending;
  std::size_t packets = 0;
  for_each_nal_unit(annexb, [&](std::span<const std::uint8_t> nal) {
    if (!worth_sending(nal)) return;
    if (pending) packets += send_nal(*pending, false, timestamp, sink);
    pending = nal;
  });
  if (pending) packets += send_nal(*pending, true, timestamp, sink);
  return packets;
}

std::size_t RtpH264Packetizer::write_header(bool marker, std::uint32_t timestamp) {
  std::uint8_t* p = packet_.data();
  p[0] = 0x80;  // version 2, no padding, no extension, no CSRC
  p[1] = static_cast<std::uint8_t>((marker ? 0x80 : 0) | options_.payload_type);
  p[2] = static_cast<std::uint8_t>(sequence_ >> 8);
  p[3] = static_cast<std::uint8_t>(sequence_);
  for (int i = 0; i < 4; ++i) {
    p[4 + i] = static_cast<std::uint8_t>(timestamp >> (24 - 8 * i));
    p[8 + i] = static_cast<std::uint8_t>(options_.ssrc >> (24 - 8 * i));
  }
  ++sequence_;
  return kRtpHeaderBytes;
}

std::size_t RtpH264Packetizer::send_nal(std::span<const std::uint8_t> nal, bool last, std::uint32_t timestamp,
                                        const PacketSink& sink) {
  const std::size_t budget = options_.max_packet_bytes - kRtpHeaderBytes;
  if (nal.size() <= budget) {  // single NAL unit packet
    const std::size_t at = write_header(last, timestamp);
    std::copy(nal.begin(), nal.end(), packet_.begin() + static_cast<std::ptrdiff_t>(at));
    sink(std::span<const std::uint8_t>(packet_.data(), at + nal.size()));
    return 1;
  }
  // FU-A: the indicator keeps F and NRI of the NAL header, the FU header its type; the NAL header
  // byte itself is not repeated in the fragments.
  const std::uint8_t indicator = static_cast<std::uint8_t>((nal[0] & 0xe0) | kFuA);
  const std::uint8_t type = nal[0] & kNalTypeMask;
  const std::size_t chunk = budget - 2;
  std::size_t packets = 0;
  for (std::size_t off = 1; off < nal.size(); off += chunk) {
    const std::size_t n = std::min(chunk, nal.size() - off);
    const bool first = off == 1, end = off + n == nal.size();
    std::size_t at = write_header(last && end, timestamp);
    packet_[at++] = indicator;
    packet_[at++] = static_cast<std::uint8_t>((first ? 0x80 : 0) | (end ? 0x40 : 0) | type);
    std::copy_n(nal.begin() + static_cast<std::ptrdiff_t>(off), n, packet_.begin() + static_cast<std::ptrdiff_t>(at));
    sink(std::span<const std::uint8_t>(packet_.data(), at + n));
    ++packets;
  }
  return packets;
}

}  // namespace labo::server
