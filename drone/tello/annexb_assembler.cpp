#include "drone/tello/annexb_assembler.hpp"

#include <algorithm>

namespace labo::tello {

namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);
constexpr std::size_t kInitialCapacity = 256 * 1024;

// First 00 00 01 at or after `from`.
std::size_t find_start_code(const std::vector<std::uint8_t>& b, std::size_t from) {
  for (std::size_t i = from; i + 2 < b.size(); ++i) {
    if (b[i + 2] > 1) {
      i += 2;  // no start code can end at i + 2, nor begin before i + 3
      continue;
    }
    if (b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 1) return i;
  }
  return kNone;
}

// The first NAL unit of an access unit (H.264 7.4.1.2.3): SEI, SPS, PPS, AUD, or a slice whose
// first_mb_in_slice is 0 (its ue(v) code is the single bit 1).
bool begins_access_unit(std::uint8_t header, std::uint8_t first_payload_byte) {
  const int type = header & 0x1F;
  if (type >= 6 && type <= 9) return true;
  return (type == 1 || type == 5) && (first_payload_byte & 0x80) != 0;
}

bool is_slice(std::uint8_t header) {
  const int type = header & 0x1F;
  return type == 1 || type == 5;
}

}  // namespace

AnnexBAssembler::AnnexBAssembler(UnitHandler on_unit, std::size_t max_unit_bytes, std::size_t datagram_bytes)
    : on_unit_(std::move(on_unit)), max_unit_bytes_(max_unit_bytes), datagram_bytes_(datagram_bytes) {
  buffer_.reserve(std::min(max_unit_bytes_, kInitialCapacity));
}

void AnnexBAssembler::reset() {
  buffer_.clear();
  scan_from_ = 0;
  unit_has_slice_ = false;
}

AnnexBAssembler::Report AnnexBAssembler::feed(std::span<const std::uint8_t> datagram) {
  Report report;
  if (datagram.empty()) return report;
  if (buffer_.size() + datagram.size() > max_unit_bytes_) {
    report.overflow = true;
    reset();
  }
  buffer_.insert(buffer_.end(), datagram.begin(), datagram.end());
  drop_junk(report);
  scan(report);
  if (datagram.size() < datagram_bytes_ && unit_has_slice_) emit(buffer_.size(), report);
  return report;
}

// The buffer must begin with a start code (00 00 01 or 00 00 00 01); what comes before one is junk.
void AnnexBAssembler::drop_junk(Report& report) {
  const std::size_t sc = find_start_code(buffer_, 0);
  std::size_t begin = 0;
  if (sc == kNone) {
    // Keep trailing zeros: they may be the beginning of a start code cut by the datagram's end.
    std::size_t zeros = 0;
    while (zeros < 3 && zeros < buffer_.size() && buffer_[buffer_.size() - 1 - zeros] == 0) ++zeros;
    begin = buffer_.size() - zeros;
  } else {
    begin = sc > 0 && buffer_[sc - 1] == 0 ? sc - 1 : sc;
  }
  if (begin == 0) return;
  report.junk_bytes += begin;
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(begin));
  scan_from_ = 0;
}

void AnnexBAssembler::scan(Report& report) {
  std::size_t from = scan_from_;
  for (std::size_t sc; (sc = find_start_code(buffer_, from)) != kNone;) {
    std::size_t header = sc + 3;
    if (header + 1 >= buffer_.size()) {  // the NAL header or its first byte is in the next datagram
      scan_from_ = sc;
      return;
    }
    if (unit_has_slice_ && begins_access_unit(buffer_[header], buffer_[header + 1])) {
      const std::size_t end = sc > 0 && buffer_[sc - 1] == 0 ? sc - 1 : sc;
      emit(end, report);
      header -= end;
    }
    if (is_slice(buffer_[header])) unit_has_slice_ = true;
    from = header + 1;
  }
  scan_from_ = std::max(from, buffer_.size() >= 2 ? buffer_.size() - 2 : std::size_t{0});
}

void AnnexBAssembler::emit(std::size_t end, Report& report) {
  if (end > 0 && on_unit_) on_unit_(std::span<const std::uint8_t>(buffer_.data(), end));
  ++report.units;
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(end));
  unit_has_slice_ = false;
  scan_from_ = 0;
}

}  // namespace labo::tello
