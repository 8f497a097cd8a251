#pragma once
// NavdataParser: one UDP 5554 datagram into a NavdataPacket, with every bound checked. Bad input gets
// a NavdataError naming what was wrong (the link counts them by kind); it never reads past the
// datagram. Unknown tags are skipped by their size; known options longer than the layout (newer
// firmware) are read as far as the layout goes; shorter ones are refused.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "drone/ardrone2/navdata_packet.hpp"

namespace labo::ardrone2 {

enum class NavdataError {
  None,
  Truncated,         // shorter than header + checksum option
  BadMagic,
  OptionTooSmall,    // option size < 4
  OptionOverrun,     // option runs past the datagram
  OptionTruncated,   // known option shorter than its layout
  NoChecksum,        // no checksum option
  BadChecksumSize,   // checksum option size != 8
  BadChecksum,
  DataAfterChecksum,
};
// Counter kind, e.g. "navdata_bad_checksum".
std::string_view to_string(NavdataError error);

struct NavdataParseResult {
  NavdataError error = NavdataError::None;
  std::string detail;  // set only on error (allocation only on the bad path)
  bool ok() const { return error == NavdataError::None; }
};

// uint32 sum of every byte (the SDK's navdata checksum over everything before the checksum option).
std::uint32_t navdata_checksum(std::span<const std::uint8_t> bytes);

class NavdataParser {
 public:
  NavdataParseResult parse(std::span<const std::uint8_t> datagram, NavdataPacket& packet) const;
};

// Client-side ordering: drop packets whose sequence does not increase; the com-watchdog bit (the
// drone restarted its count) resets the expectation. A count that starts again (a sequence of at most
// kRestartedSequenceMax after one at least that much higher: a drone rebooted under a link that stayed
// up, not a packet overtaken by the next) is accepted, and restarted() says so until the next packet.
class NavdataSequenceFilter {
 public:
  static constexpr std::uint32_t kRestartedSequenceMax = 64;
  bool accept(const NavdataPacket& packet);
  void reset() { have_last_ = false; }
  bool restarted() const { return restarted_; }

 private:
  bool have_last_ = false;
  bool restarted_ = false;
  std::uint32_t last_ = 0;
};

}  // namespace labo::ardrone2
