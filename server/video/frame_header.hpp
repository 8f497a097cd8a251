#pragma once
// The binary WebSocket video message: a 24-byte little-endian header, then one JPEG.
//   0  "LDV1"            magic ("LDR1" for the reading view, video/panel_reading_view.hpp)
//   4  u32 frame_number  the drone's frame counter
//   8  f64 capture_ms    capture (receive) time, Unix epoch milliseconds: the page subtracts it from
//                        its own clock to show glass-to-browser latency
//  16  u8  camera        0 front, 1 bottom
//  17  u8  reserved
//  18  u16 reserved
//  20  u32 jpeg_bytes
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

namespace labo::server {

struct FrameHeader {
  static constexpr std::size_t kSize = 24;
  std::uint32_t frame_number = 0;
  double capture_unix_ms = 0;
  std::uint8_t camera = 0;
  std::uint32_t jpeg_bytes = 0;

  // Writes the header into the first kSize bytes of `out` (which must be at least that long).
  void write(char* out, std::string_view magic = "LDV1") const;
  static std::optional<FrameHeader> read(std::string_view message, std::string_view magic = "LDV1");
};

}  // namespace labo::server
