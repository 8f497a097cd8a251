#include "drone/ardrone2/pave.hpp"

#include <algorithm>
#include <cstring>

#include "drone/ardrone2/byte_io.hpp"

namespace labo::ardrone2 {

namespace {
constexpr std::uint8_t kSignature[4] = {'P', 'a', 'V', 'E'};
constexpr std::size_t kMinimalHeaderBytes = 12;  // signature, version, codec, header_size, payload_size
}  // namespace

std::string_view to_string(PaveStatus status) {
  switch (status) {
    case PaveStatus::Frame: return "pave_frame";
    case PaveStatus::NeedMore: return "pave_need_more";
    case PaveStatus::SkippedJunk: return "pave_junk";
    case PaveStatus::BadHeaderSize: return "pave_bad_header_size";
    case PaveStatus::PayloadTooLarge: return "pave_payload_too_large";
    case PaveStatus::ChunkError: return "pave_chunk_error";
    case PaveStatus::ChunkBuffered: return "pave_chunk_buffered";
  }
  return "pave_error";
}

bool parse_pave_header(std::span<const std::uint8_t> b, PaveHeader& h) {
  if (b.size() < kPaveHeaderBytes || std::memcmp(b.data(), kSignature, 4) != 0) return false;
  h.version = b[4];
  h.codec = b[5];
  h.header_size = read_le<std::uint16_t>(b, 6);
  h.payload_size = read_le<std::uint32_t>(b, 8);
  h.encoded_width = read_le<std::uint16_t>(b, 12);
  h.encoded_height = read_le<std::uint16_t>(b, 14);
  h.display_width = read_le<std::uint16_t>(b, 16);
  h.display_height = read_le<std::uint16_t>(b, 18);
  h.frame_number = read_le<std::uint32_t>(b, 20);
  h.timestamp_ms = read_le<std::uint32_t>(b, 24);
  h.total_chunks = b[28];
  h.chunk_index = b[29];
  h.frame_type = b[30];
  h.control = b[31];
  h.stream_byte_position_lw = read_le<std::uint32_t>(b, 32);
  h.stream_byte_position_uw = read_le<std::uint32_t>(b, 36);
  h.stream_id = read_le<std::uint16_t>(b, 40);
  h.total_slices = b[42];
  h.slice_index = b[43];
  h.header1_size = b[44];
  h.header2_size = b[45];
  h.advertised_size = read_le<std::uint32_t>(b, 48);
  return true;
}

PaveDemuxer::PaveDemuxer(std::size_t max_payload_bytes) : max_payload_(max_payload_bytes) {
  buffer_.reserve(64 * 1024);
}

void PaveDemuxer::reset() {
  buffer_.clear();
  read_ = 0;
  chunks_.clear();
  in_chunked_frame_ = false;
}

void PaveDemuxer::feed(std::span<const std::uint8_t> bytes) {
  // Compact before appending so the buffer does not grow with the stream.
  if (read_ > 0 && (read_ >= buffer_.size() / 2 || buffer_.size() + bytes.size() > buffer_.capacity())) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(read_));
    read_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

PaveStatus PaveDemuxer::skip(std::size_t n, PaveStatus why) {
  read_ += n;
  last_skipped_ = n;
  return why;
}

PaveStatus PaveDemuxer::next(PaveFrame& frame) {
  last_skipped_ = 0;
  const std::span<const std::uint8_t> avail(buffer_.data() + read_, buffer_.size() - read_);
  const auto found = std::search(avail.begin(), avail.end(), std::begin(kSignature), std::end(kSignature));
  const auto offset = static_cast<std::size_t>(found - avail.begin());
  if (offset > 0) {
    // Keep up to 3 trailing bytes: they may be the start of a signature split across reads.
    const std::size_t junk = found == avail.end() ? (avail.size() > 3 ? avail.size() - 3 : 0) : offset;
    if (junk > 0) return skip(junk, PaveStatus::SkippedJunk);
    return PaveStatus::NeedMore;
  }
  if (avail.size() < kMinimalHeaderBytes) return PaveStatus::NeedMore;
  const auto header_size = read_le<std::uint16_t>(avail, 6);
  const auto payload_size = read_le<std::uint32_t>(avail, 8);
  if (header_size < kPaveHeaderBytes || header_size > kPaveMaxHeaderBytes) return skip(4, PaveStatus::BadHeaderSize);
  if (payload_size > max_payload_) return skip(4, PaveStatus::PayloadTooLarge);
  if (avail.size() < header_size + std::size_t{payload_size}) return PaveStatus::NeedMore;
  PaveHeader header;
  parse_pave_header(avail, header);
  read_ += header_size + std::size_t{payload_size};
  return assemble(header, avail.subspan(header_size, payload_size), frame);
}

PaveStatus PaveDemuxer::assemble(const PaveHeader& header, std::span<const std::uint8_t> payload, PaveFrame& frame) {
  if (header.total_chunks <= 1) {
    // A whole frame after an unfinished chunked one: the partial one is lost.
    in_chunked_frame_ = false;
    frame.header = header;
    frame.payload = payload;
    return PaveStatus::Frame;
  }
  const bool continues = in_chunked_frame_ && header.frame_number == chunk_header_.frame_number &&
                         header.chunk_index == chunk_header_.chunk_index + 1;
  if (header.chunk_index == 0) {
    const bool had_partial = in_chunked_frame_;
    chunks_.assign(payload.begin(), payload.end());
    chunk_header_ = header;
    in_chunked_frame_ = true;
    if (had_partial) return PaveStatus::ChunkError;
  } else if (continues) {
    chunks_.insert(chunks_.end(), payload.begin(), payload.end());
    chunk_header_.chunk_index = header.chunk_index;
  } else {
    in_chunked_frame_ = false;
    return PaveStatus::ChunkError;
  }
  if (chunk_header_.chunk_index + 1 < header.total_chunks) return PaveStatus::ChunkBuffered;
  in_chunked_frame_ = false;
  frame.header = chunk_header_;
  frame.header.payload_size = static_cast<std::uint32_t>(chunks_.size());
  frame.payload = chunks_;
  return PaveStatus::Frame;
}

void PaveWriter::write(PaveHeader h, std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out) const {
  h.payload_size = static_cast<std::uint32_t>(payload.size());
  if (h.header_size < kPaveHeaderBytes) h.header_size = kPaveHeaderBytes;
  const std::size_t start = out.size();
  out.insert(out.end(), std::begin(kSignature), std::end(kSignature));
  out.push_back(h.version);
  out.push_back(h.codec);
  write_le(out, h.header_size);
  write_le(out, h.payload_size);
  write_le(out, h.encoded_width);
  write_le(out, h.encoded_height);
  write_le(out, h.display_width);
  write_le(out, h.display_height);
  write_le(out, h.frame_number);
  write_le(out, h.timestamp_ms);
  for (std::uint8_t v : {h.total_chunks, h.chunk_index, h.frame_type, h.control}) out.push_back(v);
  write_le(out, h.stream_byte_position_lw);
  write_le(out, h.stream_byte_position_uw);
  write_le(out, h.stream_id);
  for (std::uint8_t v : {h.total_slices, h.slice_index, h.header1_size, h.header2_size}) out.push_back(v);
  out.push_back(0);
  out.push_back(0);
  write_le(out, h.advertised_size);
  out.resize(start + h.header_size, 0);  // reserved bytes (12, or 16 with a 68-byte header)
  out.insert(out.end(), payload.begin(), payload.end());
}

}  // namespace labo::ardrone2
