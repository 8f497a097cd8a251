#include "server/video/frame_header.hpp"

#include "server/video/wire_bytes.hpp"

namespace labo::server {

using wire::get;
using wire::put;

void FrameHeader::write(char* out, std::string_view magic) const {
  std::memcpy(out, magic.data(), 4);
  put(out, 4, frame_number);
  put(out, 8, capture_unix_ms);
  put(out, 16, camera);
  put<std::uint8_t>(out, 17, 0);
  put<std::uint16_t>(out, 18, 0);
  put(out, 20, jpeg_bytes);
}

std::optional<FrameHeader> FrameHeader::read(std::string_view m, std::string_view magic) {
  if (m.size() < kSize || m.substr(0, 4) != magic) return std::nullopt;
  FrameHeader h;
  h.frame_number = get<std::uint32_t>(m, 4);
  h.capture_unix_ms = get<double>(m, 8);
  h.camera = get<std::uint8_t>(m, 16);
  h.jpeg_bytes = get<std::uint32_t>(m, 20);
  if (h.jpeg_bytes != m.size() - kSize) return std::nullopt;
  return h;
}

}  // namespace labo::server
