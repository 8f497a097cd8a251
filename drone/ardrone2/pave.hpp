#pragma once
// PaVE, Parrot's video encapsulation on TCP 5555 (shared/notes/ardrone.md §3): a header (64 bytes, 68
// on some firmware; the payload always starts at header_size), then payload_size bytes of H.264.
// PaveDemuxer turns a byte stream cut anywhere into frames, resynchronising on "PaVE" after junk;
// PaveWriter produces the stream (the emulator, tests).
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace labo::ardrone2 {

inline constexpr std::size_t kPaveHeaderBytes = 64;
inline constexpr std::size_t kPaveMaxHeaderBytes = 256;      // sanity limit on header_size
inline constexpr std::size_t kPaveDefaultMaxPayload = 1 << 20;  // 1 MiB: a 720p IDR is ~100 kB
inline constexpr std::uint8_t kPaveCodecH264 = 4;

enum class PaveFrameType : std::uint8_t { Unknown = 0, Idr = 1, I = 2, P = 3, Headers = 4 };

struct PaveHeader {
  std::uint8_t version = 2;
  std::uint8_t codec = kPaveCodecH264;
  std::uint16_t header_size = kPaveHeaderBytes;
  std::uint32_t payload_size = 0;
  std::uint16_t encoded_width = 640, encoded_height = 368;
  std::uint16_t display_width = 640, display_height = 360;
  std::uint32_t frame_number = 0;
  std::uint32_t timestamp_ms = 0;
  std::uint8_t total_chunks = 1, chunk_index = 0;
  std::uint8_t frame_type = static_cast<std::uint8_t>(PaveFrameType::P);
  std::uint8_t control = 0;
  std::uint32_t stream_byte_position_lw = 0, stream_byte_position_uw = 0;
  std::uint16_t stream_id = 0;
  std::uint8_t total_slices = 1, slice_index = 0;
  std::uint8_t header1_size = 0, header2_size = 0;  // SPS, PPS sizes with start codes (IDR frames)
  std::uint32_t advertised_size = 0;
};

enum class PaveStatus {
  Frame,            // `frame` holds a complete frame (all chunks joined)
  NeedMore,         // feed more bytes
  SkippedJunk,      // bytes before a signature were discarded (count in skipped_bytes())
  BadHeaderSize,    // header_size < 64 or > 256: signature skipped, resync
  PayloadTooLarge,  // payload_size beyond the limit: signature skipped, resync
  ChunkError,       // chunk out of order or of another frame: partial frame dropped
  ChunkBuffered,    // one chunk of a multi-chunk frame kept; call next() again
};
std::string_view to_string(PaveStatus status);  // counter kind, e.g. "pave_junk"

struct PaveFrame {
  PaveHeader header;
  std::span<const std::uint8_t> payload;  // valid until the next feed() or next()
};

class PaveDemuxer {
 public:
  explicit PaveDemuxer(std::size_t max_payload_bytes = kPaveDefaultMaxPayload);
  void feed(std::span<const std::uint8_t> bytes);
  // Call until NeedMore. Never stalls on garbage: every status but NeedMore consumes bytes.
  PaveStatus next(PaveFrame& frame);
  std::size_t skipped_bytes() const { return last_skipped_; }
  std::size_t buffered_bytes() const { return buffer_.size() - read_; }
  void reset();

 private:
  PaveStatus skip(std::size_t n, PaveStatus why);
  PaveStatus assemble(const PaveHeader& header, std::span<const std::uint8_t> payload, PaveFrame& frame);
  std::size_t max_payload_;
  std::vector<std::uint8_t> buffer_;
  std::size_t read_ = 0;
  std::size_t last_skipped_ = 0;
  std::vector<std::uint8_t> chunks_;  // joined payload of a multi-chunk frame
  PaveHeader chunk_header_;
  bool in_chunked_frame_ = false;
};

// Parses a header at the start of `bytes` (>= 64 bytes, starting with "PaVE"); false otherwise.
bool parse_pave_header(std::span<const std::uint8_t> bytes, PaveHeader& header);

class PaveWriter {
 public:
  // Appends header + payload to `out`. header.payload_size is set from the payload; header_size may
  // be 64 or 68 (the 4 extra bytes are zero).
  void write(PaveHeader header, std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out) const;
};

}  // namespace labo::ardrone2
