#include "drone/ardrone2/navdata_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "drone/ardrone2/byte_io.hpp"
#include "drone/ardrone2/navdata_parser.hpp"

namespace labo::ardrone2 {

namespace {

template <typename T>
T saturate(double v) {
  if (!std::isfinite(v)) return T{};
  const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

void write_value(std::vector<std::uint8_t>& out, WireType type, double v) {
  switch (type) {
    case WireType::U8: out.push_back(saturate<std::uint8_t>(v)); break;
    case WireType::I16: write_le(out, saturate<std::int16_t>(v)); break;
    case WireType::U16: write_le(out, saturate<std::uint16_t>(v)); break;
    case WireType::I32:
    case WireType::Bool32: write_le(out, saturate<std::int32_t>(v)); break;
    case WireType::U32: write_le(out, saturate<std::uint32_t>(v)); break;
    case WireType::F32: write_le(out, static_cast<float>(v)); break;
    case WireType::F64: write_le(out, v); break;
  }
}

}  // namespace

void NavdataBuilder::build(const NavdataPacket& packet, std::vector<std::uint8_t>& out,
                           std::span<const std::vector<std::uint8_t>> extra) const {
  out.clear();
  write_le(out, packet.magic);
  write_le(out, packet.state);
  write_le(out, packet.sequence);
  write_le(out, packet.vision_defined);
  for (const auto& spec : navdata_option_specs()) {
    if (!packet.has(spec.tag)) continue;
    const auto& values = packet.option(spec.tag);
    write_le(out, spec.tag);
    write_le(out, spec.size);
    std::size_t index = 0;
    for (const auto& f : spec.fields) {
      for (std::size_t k = 0; k < f.count; ++k) write_value(out, f.type, values.raw[index++]);
    }
  }
  for (const auto& option : extra) out.insert(out.end(), option.begin(), option.end());
  const std::uint32_t cks = navdata_checksum(out);
  write_le(out, static_cast<std::uint16_t>(kTagChecksum));
  write_le(out, kChecksumOptionBytes);
  write_le(out, cks);
}

std::vector<std::uint8_t> make_raw_option(std::uint16_t tag, std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out(kOptionHeaderBytes + body.size());
  write_le_at(std::span(out), 0, tag);
  write_le_at(std::span(out), 2, static_cast<std::uint16_t>(body.size() + kOptionHeaderBytes));
  if (!body.empty()) std::memcpy(out.data() + kOptionHeaderBytes, body.data(), body.size());
  return out;
}

}  // namespace labo::ardrone2
