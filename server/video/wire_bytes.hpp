#pragma once
// Little-endian fields of the binary WebSocket messages (frame_header, access_unit_wire).
#include <bit>
#include <cstddef>
#include <cstring>
#include <string_view>

namespace labo::wire {

static_assert(std::endian::native == std::endian::little, "the wire format is little-endian; add byte swaps for this host");

template <typename T>
void put(char* out, std::size_t at, T v) {
  std::memcpy(out + at, &v, sizeof(T));
}

// The caller has checked that `in` holds at + sizeof(T) bytes.
template <typename T>
T get(std::string_view in, std::size_t at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  return v;
}

}  // namespace labo::wire
