#pragma once
// Little-endian reads and writes for the AR.Drone wire formats (navdata, PaVE). Reads never run past
// the span: callers check the size first; these only assemble bytes (memcpy avoids unaligned access).
#include <cstdint>
#include <bit>
#include <cstring>
#include <span>
#include <vector>

namespace labo::ardrone2 {

template <typename T>
T read_le(std::span<const std::uint8_t> bytes, std::size_t offset) {
  T value{};
  std::memcpy(&value, bytes.data() + offset, sizeof(T));  // x86/ARM little-endian hosts only
  return value;
}

template <typename T>
void write_le(std::vector<std::uint8_t>& out, T value) {
  const std::size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

template <typename T>
void write_le_at(std::span<std::uint8_t> bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

static_assert(std::endian::native == std::endian::little, "the wire formats are little-endian");

}  // namespace labo::ardrone2
