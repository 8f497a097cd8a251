#include "drone/ardrone2/navdata_parser.hpp"

#include "drone/ardrone2/byte_io.hpp"

namespace labo::ardrone2 {

std::string_view to_string(NavdataError error) {
  switch (error) {
    case NavdataError::None: return "navdata_ok";
    case NavdataError::Truncated: return "navdata_truncated";
    case NavdataError::BadMagic: return "navdata_bad_magic";
    case NavdataError::OptionTooSmall: return "navdata_option_too_small";
    case NavdataError::OptionOverrun: return "navdata_option_overrun";
    case NavdataError::OptionTruncated: return "navdata_option_truncated";
    case NavdataError::NoChecksum: return "navdata_no_checksum";
    case NavdataError::BadChecksumSize: return "navdata_bad_checksum_size";
    case NavdataError::BadChecksum: return "navdata_bad_checksum";
    case NavdataError::DataAfterChecksum: return "navdata_data_after_checksum";
  }
  return "navdata_error";
}

std::uint32_t navdata_checksum(std::span<const std::uint8_t> bytes) {
  std::uint32_t sum = 0;
  for (std::uint8_t b : bytes) sum += b;
  return sum;
}

namespace {

NavdataParseResult fail(NavdataError error, std::string detail) { return {error, std::move(detail)}; }

double read_value(std::span<const std::uint8_t> bytes, std::size_t offset, WireType type) {
  switch (type) {
    case WireType::U8: return bytes[offset];
    case WireType::I16: return read_le<std::int16_t>(bytes, offset);
    case WireType::U16: return read_le<std::uint16_t>(bytes, offset);
    case WireType::I32:
    case WireType::Bool32: return read_le<std::int32_t>(bytes, offset);
    case WireType::U32: return read_le<std::uint32_t>(bytes, offset);
    case WireType::F32: return read_le<float>(bytes, offset);
    case WireType::F64: return read_le<double>(bytes, offset);
  }
  return 0;
}

void decode_option(const NavdataOptionSpec& spec, std::span<const std::uint8_t> body, NavdataOptionValues& out) {
  std::size_t offset = 0, index = 0;
  for (const auto& f : spec.fields) {
    const std::size_t step = wire_size(f.type);
    for (std::size_t k = 0; k < f.count; ++k, offset += step) out.raw[index++] = read_value(body, offset, f.type);
  }
}

}  // namespace

NavdataParseResult NavdataParser::parse(std::span<const std::uint8_t> data, NavdataPacket& packet) const {
  packet.clear();
  if (data.size() < kNavdataHeaderBytes + kChecksumOptionBytes) {
    return fail(NavdataError::Truncated, "datagram of " + std::to_string(data.size()) +
                                             " bytes, expected at least 24 (header + checksum option)");
  }
  packet.magic = read_le<std::uint32_t>(data, 0);
  if (packet.magic != kNavdataMagic && packet.magic != kNavdataMagicAlt) {
    return fail(NavdataError::BadMagic, "magic " + std::to_string(packet.magic) + ", expected 0x55667788");
  }
  packet.state = read_le<std::uint32_t>(data, 4);
  packet.sequence = read_le<std::uint32_t>(data, 8);
  packet.vision_defined = read_le<std::uint32_t>(data, 12);

  std::size_t offset = kNavdataHeaderBytes;
  while (offset + kOptionHeaderBytes <= data.size()) {
    const auto tag = read_le<std::uint16_t>(data, offset);
    const auto size = read_le<std::uint16_t>(data, offset + 2);
    if (size < kOptionHeaderBytes) {
      return fail(NavdataError::OptionTooSmall, "option tag " + std::to_string(tag) + " at byte " +
                                                    std::to_string(offset) + " has size " + std::to_string(size) + " < 4");
    }
    if (offset + size > data.size()) {
      return fail(NavdataError::OptionOverrun, "option tag " + std::to_string(tag) + " of size " + std::to_string(size) +
                                                   " at byte " + std::to_string(offset) + " runs past the " +
                                                   std::to_string(data.size()) + "-byte datagram");
    }
    if (tag == kTagChecksum) {
      if (size != kChecksumOptionBytes) {
        return fail(NavdataError::BadChecksumSize, "checksum option of size " + std::to_string(size) + ", expected 8");
      }
      packet.checksum_received = read_le<std::uint32_t>(data, offset + 4);
      packet.checksum_computed = navdata_checksum(data.first(offset));
      if (offset + size != data.size()) {
        return fail(NavdataError::DataAfterChecksum,
                    std::to_string(data.size() - offset - size) + " bytes after the checksum option");
      }
      if (packet.checksum_received != packet.checksum_computed) {
        return fail(NavdataError::BadChecksum, "checksum " + std::to_string(packet.checksum_received) +
                                                   ", computed " + std::to_string(packet.checksum_computed));
      }
      packet.checksum_ok = true;
      return {};
    }
    if (const NavdataOptionSpec* spec = find_option_spec(tag)) {
      if (size < spec->size) {
        return fail(NavdataError::OptionTruncated, "option " + std::string(spec->name) + " of size " +
                                                       std::to_string(size) + ", expected " + std::to_string(spec->size));
      }
      auto& values = packet.option(tag);
      decode_option(*spec, data.subspan(offset + kOptionHeaderBytes, size - kOptionHeaderBytes), values);
      values.present = true;
      values.wire_size = size;
    } else if (packet.unknown.size() < 64) {
      packet.unknown.push_back({tag, size});
    }
    offset += size;
  }
  return fail(NavdataError::NoChecksum, "no checksum option (tag 0xFFFF) before the end of the datagram");
}

bool NavdataSequenceFilter::accept(const NavdataPacket& packet) {
  if (packet.state_bit(kStateComWatchdog)) have_last_ = false;
  restarted_ = have_last_ && packet.sequence <= kRestartedSequenceMax && last_ >= packet.sequence + kRestartedSequenceMax;
  if (have_last_ && packet.sequence <= last_ && !restarted_) return false;
  have_last_ = true;
  last_ = packet.sequence;
  return true;
}

}  // namespace labo::ardrone2
