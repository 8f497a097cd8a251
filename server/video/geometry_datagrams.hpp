#pragma once
// A frame's overlay geometry (the `overlay` JSON of video/overlay_geometry.hpp) cut into UDP
// datagrams for a media server that relays each datagram as one data-channel message (a Janus
// streaming mount point's data port): Janus reads a datagram into an MTU-sized buffer, so a
// geometry larger than one is sent in parts. Each datagram is text: the line
// "LDG1 <frame> <part> <count>\n" and then part `part` (0-based) of `count` of the JSON, cut where
// no UTF-8 sequence is split (a text data-channel message must be valid UTF-8). The page joins a
// frame's parts in order (web/janus_view.js GeometryParts). No allocation per frame.
#include <array>
#include <cstdint>
#include <span>
#include <string_view>

namespace labo::server {

class GeometryDatagrams {
 public:
  // At most this many bytes per datagram, header included: within a 1500-byte MTU with IP/UDP
  // headers, and Janus's relay buffer.
  static constexpr std::size_t kMaxDatagram = 1400;
  static constexpr std::size_t kMaxHeader = 40;  // "LDG1 4294967295 65535 65535\n" and room

  // Calls `send` with each datagram of `geometry` for frame `frame`, in order; how many. A geometry
  // of more than 65535 parts (tens of megabytes; never one frame's overlays) is not sent: 0.
  template <typename Send>
  std::size_t split(std::uint32_t frame, std::string_view geometry, Send&& send) {
    const std::size_t count = part_count(geometry);
    if (count == 0) return 0;
    std::size_t offset = 0;
    for (std::size_t part = 0; part < count; ++part) {
      const std::size_t length = slice_length(geometry, offset);
      send(datagram(frame, part, count, geometry.substr(offset, length)));
      offset += length;
    }
    return count;
  }

 private:
  // Parts of at most kMaxDatagram - kMaxHeader bytes, none ending inside a UTF-8 sequence.
  static std::size_t part_count(std::string_view geometry);
  static std::size_t slice_length(std::string_view geometry, std::size_t offset);
  std::span<const char> datagram(std::uint32_t frame, std::size_t part, std::size_t count, std::string_view slice);

  std::array<char, kMaxDatagram> buffer_{};
};

}  // namespace labo::server
