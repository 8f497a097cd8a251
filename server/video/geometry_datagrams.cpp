#include "server/video/geometry_datagrams.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace labo::server {

namespace {
constexpr std::size_t kMaxParts = 65535;
bool continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }
}  // namespace

std::size_t GeometryDatagrams::slice_length(std::string_view geometry, std::size_t offset) {
  const std::size_t room = kMaxDatagram - kMaxHeader;
  if (geometry.size() - offset <= room) return geometry.size() - offset;
  std::size_t end = offset + room;
  while (end > offset && continuation(geometry[end])) --end;  // back to the start of a sequence
  return end > offset ? end - offset : room;                  // invalid UTF-8: cut anyway
}

std::size_t GeometryDatagrams::part_count(std::string_view geometry) {
  if (geometry.empty()) return 0;
  std::size_t parts = 0;
  for (std::size_t offset = 0; offset < geometry.size(); offset += slice_length(geometry, offset))
    if (++parts > kMaxParts) return 0;
  return parts;
}

std::span<const char> GeometryDatagrams::datagram(std::uint32_t frame, std::size_t part, std::size_t count,
                                                  std::string_view slice) {
  const int header = std::snprintf(buffer_.data(), kMaxHeader, "LDG1 %u %zu %zu\n", frame, part, count);
  const auto n = static_cast<std::size_t>(std::max(header, 0));
  std::memcpy(buffer_.data() + n, slice.data(), slice.size());
  return {buffer_.data(), n + slice.size()};
}

}  // namespace labo::server
