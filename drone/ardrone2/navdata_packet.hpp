#pragma once
// One decoded navdata packet: the header, every known option's raw values (flattened in the order of
// navdata_schema.hpp) and the tags of unknown options that were skipped by their size. A packet is
// built once and parsed into again and again: its value arrays keep their storage.
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "drone/ardrone2/navdata_schema.hpp"

namespace labo::ardrone2 {

inline constexpr std::uint32_t kNavdataMagic = 0x55667788u;
inline constexpr std::uint32_t kNavdataMagicAlt = 0x55667789u;  // accepted (seen in node-ar-drone), never sent
inline constexpr std::size_t kNavdataHeaderBytes = 16;

struct NavdataOptionValues {
  bool present = false;
  std::uint16_t wire_size = 0;  // as received (may exceed the known layout on newer firmware)
  std::vector<double> raw;      // one per value of the schema, raw wire units
};

struct UnknownOption {
  std::uint16_t tag = 0;
  std::uint16_t size = 0;
};

class NavdataPacket {
 public:
  NavdataPacket();

  std::uint32_t magic = kNavdataMagic;
  std::uint32_t state = 0;
  std::uint32_t sequence = 0;
  std::uint32_t vision_defined = 0;
  bool checksum_ok = false;
  std::uint32_t checksum_received = 0;
  std::uint32_t checksum_computed = 0;
  std::vector<UnknownOption> unknown;

  // Marks every option absent (keeps storage).
  void clear();
  bool has(std::uint16_t tag) const { return tag < kKnownOptionCount && options_[tag].present; }
  bool state_bit(int bit) const { return (state >> bit) & 1u; }
  const NavdataOptionValues& option(std::uint16_t tag) const { return options_.at(tag); }
  NavdataOptionValues& option(std::uint16_t tag) { return options_.at(tag); }
  // Raw value of a field (index into an array field); throws std::out_of_range for unknown names.
  double raw(std::uint16_t tag, std::string_view field, std::size_t index = 0) const;
  // Sets a field's raw value and marks the option present (builders, the emulator).
  void set(std::uint16_t tag, std::string_view field, double value, std::size_t index = 0);
  // Marks an option present with all values zero.
  void add_option(std::uint16_t tag);

 private:
  std::size_t index_of(std::uint16_t tag, std::string_view field, std::size_t index) const;
  std::array<NavdataOptionValues, kKnownOptionCount> options_;
};

// Demo option: major control state (high 16 bits of ctrl_state).
inline int control_state_major(std::uint32_t ctrl_state) { return static_cast<int>(ctrl_state >> 16); }
// Option `time`: 11 bits of seconds, 21 bits of microseconds.
inline double navdata_time_seconds(std::uint32_t time) {
  return static_cast<double>(time >> 21) + static_cast<double>(time & 0x1FFFFFu) * 1e-6;
}

}  // namespace labo::ardrone2
