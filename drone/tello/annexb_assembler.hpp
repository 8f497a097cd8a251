#pragma once
// AnnexBAssembler: an H.264 Annex-B byte stream that arrives cut into UDP datagrams (the Tello's
// video on port 11111: raw H.264, NAL units split over datagrams of at most 1460 bytes) back into
// access units, one decodable picture each (SPS/PPS/SEI joined to the slice that follows).
//
// A unit ends at whichever comes first: a datagram shorter than the stream's datagram size (the
// Tello ends every frame with one; no added latency), or the first NAL unit of the next access unit
// (an AUD, SPS, PPS or SEI, or a slice with first_mb_in_slice = 0, after a slice; H.264 7.4.1.2.3),
// which also catches a frame whose size is an exact multiple of 1460 one frame later. Bytes before
// the first start code of a unit are junk: dropped and counted. A unit over `max_unit_bytes` is
// dropped whole and the stream resynchronises at the next start code. The buffer is reused: steady
// state does not allocate.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace labo::tello {

inline constexpr std::size_t kTelloVideoDatagramBytes = 1460;
inline constexpr std::size_t kDefaultMaxUnitBytes = 1u << 20;  // a 960x720 IDR is ~50-150 kB

class AnnexBAssembler {
 public:
  using UnitHandler = std::function<void(std::span<const std::uint8_t> access_unit)>;
  struct Report {
    std::size_t units = 0;       // access units handed out by this feed
    std::size_t junk_bytes = 0;  // dropped before a start code
    bool overflow = false;       // a unit grew past max_unit_bytes and was dropped
  };

  explicit AnnexBAssembler(UnitHandler on_unit, std::size_t max_unit_bytes = kDefaultMaxUnitBytes,
                           std::size_t datagram_bytes = kTelloVideoDatagramBytes);
  // One datagram, in arrival order. The handler sees each completed unit (valid during the call).
  Report feed(std::span<const std::uint8_t> datagram);
  // A new stream (reconnection): drop partial data.
  void reset();
  std::size_t buffered_bytes() const { return buffer_.size(); }

 private:
  void emit(std::size_t end, Report& report);
  void drop_junk(Report& report);
  void scan(Report& report);

  UnitHandler on_unit_;
  std::size_t max_unit_bytes_;
  std::size_t datagram_bytes_;
  std::vector<std::uint8_t> buffer_;  // the unit so far, from its first start code
  std::size_t scan_from_ = 0;         // next byte where a start code may begin
  bool unit_has_slice_ = false;
};

}  // namespace labo::tello
