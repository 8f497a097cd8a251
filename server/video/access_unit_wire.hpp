#pragma once
// The binary WebSocket message of the H.264 path: a 28-byte little-endian header, then one access
// unit as the drone sent it (Annex-B, every slice of the frame; no re-encoding on the server).
//   0  "LDH1"            magic
//   4  u32 frame_number  the drone's frame counter (the overlay geometry of the frame carries it too)
//   8  f64 capture_ms    capture (receive) time, Unix epoch milliseconds, as in the JPEG header
//  16  u8  camera        0 front, 1 bottom
//  17  u8  flags         bit 0: keyframe (an IDR with SPS and PPS: a decoder can start here)
//  18  u16 width         display size in pixels
//  20  u16 height
//  22  u8  rendition     0 the drone's own stream, 1 the server's shared low rendition (video/rendition.hpp)
//  23  u8  reserved
//  24  u32 annexb_bytes
#include <cstdint>
#include <optional>
#include <string_view>

#include "drone/drone_link.hpp"
#include "server/lab/flight_service.hpp"
#include "server/video/wire_buffer_pool.hpp"

namespace labo::server {

struct AccessUnitHeader {
  static constexpr std::size_t kSize = 28;
  std::uint32_t frame_number = 0;
  double capture_unix_ms = 0;
  std::uint8_t camera = 0;
  bool keyframe = false;
  std::uint16_t width = 0, height = 0;
  Rendition rendition = Rendition::Source;
  std::uint32_t annexb_bytes = 0;

  // Writes the header into the first kSize bytes of `out` (which must be at least that long).
  void write(char* out) const;
  // Nullopt unless `message` is a whole access-unit message (magic, size consistent).
  static std::optional<AccessUnitHeader> read(std::string_view message);
};

// Copies each access unit behind its header into a pooled buffer (one copy, shared by every viewer).
class AccessUnitPacker {
 public:
  AccessUnitPacker() : pool_(32, 64 * 1024) {}
  WireAccessUnit pack(const EncodedVideo& unit, double capture_unix_ms, Rendition rendition = Rendition::Source);
  std::size_t buffers() const { return pool_.size(); }  // pooled so far (bounded by the viewers' queues)

 private:
  WireBufferPool pool_;
};

}  // namespace labo::server
