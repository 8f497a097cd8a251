#pragma once
// NavdataBuilder: serializes a NavdataPacket as the drone does (header, every present known option in
// tag order with its SDK layout, then the checksum option). Used by the emulator, the tests and the
// fuzz corpus. Extra raw options (unknown tags, deliberately broken ones) can be appended for tests.
#include <cstdint>
#include <span>
#include <vector>

#include "drone/ardrone2/navdata_packet.hpp"

namespace labo::ardrone2 {

class NavdataBuilder {
 public:
  // Writes the packet into `out` (cleared; capacity reused). `extra` options (each a complete
  // tag+size+body byte run) go after the known ones and before the checksum.
  void build(const NavdataPacket& packet, std::vector<std::uint8_t>& out,
             std::span<const std::vector<std::uint8_t>> extra = {}) const;
};

// A complete option: tag, size = 4 + body size, body.
std::vector<std::uint8_t> make_raw_option(std::uint16_t tag, std::span<const std::uint8_t> body);

}  // namespace labo::ardrone2
