#include "server/video/access_unit_wire.hpp"

#include <algorithm>
#include <cstring>

#include "server/video/wire_bytes.hpp"

namespace labo::server {

using wire::get;
using wire::put;

namespace {
std::uint16_t u16(int v) { return static_cast<std::uint16_t>(std::clamp(v, 0, 0xFFFF)); }
}  // namespace

void AccessUnitHeader::write(char* out) const {
  std::memcpy(out, "LDH1", 4);
  put(out, 4, frame_number);
  put(out, 8, capture_unix_ms);
  put(out, 16, camera);
  put<std::uint8_t>(out, 17, keyframe ? 1 : 0);
  put(out, 18, width);
  put(out, 20, height);
  put(out, 22, static_cast<std::uint8_t>(rendition));
  put<std::uint8_t>(out, 23, 0);
  put(out, 24, annexb_bytes);
}

std::optional<AccessUnitHeader> AccessUnitHeader::read(std::string_view m) {
  if (m.size() < kSize || m.substr(0, 4) != "LDH1") return std::nullopt;
  AccessUnitHeader h;
  h.frame_number = get<std::uint32_t>(m, 4);
  h.capture_unix_ms = get<double>(m, 8);
  h.camera = get<std::uint8_t>(m, 16);
  h.keyframe = (get<std::uint8_t>(m, 17) & 1) != 0;
  h.width = get<std::uint16_t>(m, 18);
  h.height = get<std::uint16_t>(m, 20);
  const auto rendition = get<std::uint8_t>(m, 22);
  if (rendition > static_cast<std::uint8_t>(Rendition::Low)) return std::nullopt;
  h.rendition = static_cast<Rendition>(rendition);
  h.annexb_bytes = get<std::uint32_t>(m, 24);
  if (h.annexb_bytes != m.size() - kSize) return std::nullopt;
  return h;
}

WireAccessUnit AccessUnitPacker::pack(const EncodedVideo& unit, double capture_unix_ms, Rendition rendition) {
  const AccessUnitHeader header{unit.frame_number, capture_unix_ms, static_cast<std::uint8_t>(unit.camera), unit.keyframe,
                                u16(unit.width), u16(unit.height), rendition, static_cast<std::uint32_t>(unit.annexb.size())};
  auto buffer = pool_.acquire();
  buffer->resize(AccessUnitHeader::kSize + unit.annexb.size());
  header.write(buffer->data());
  std::memcpy(buffer->data() + AccessUnitHeader::kSize, unit.annexb.data(), unit.annexb.size());
  WireAccessUnit out;
  out.frame_number = unit.frame_number;
  out.capture_unix_ms = capture_unix_ms;
  out.camera = unit.camera;
  out.keyframe = unit.keyframe;
  out.rendition = rendition;
  out.wire = std::move(buffer);
  return out;
}

}  // namespace labo::server
