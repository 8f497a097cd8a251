#include "drone/ardrone2/link_receiver.hpp"

#include <string>

#include "drone/ardrone2/wire_signs.hpp"

namespace labo::ardrone2 {

NavdataReceiver::NavdataReceiver(LinkCounters& counters, Handler handler)
    : counters_(counters), handler_(std::move(handler)) {}

VideoReceiver::VideoReceiver(LinkCounters& counters, Handler handler, EncodedHandler encoded)
    : counters_(counters), handler_(std::move(handler)), encoded_(std::move(encoded)) {}

bool NavdataReceiver::datagram(std::span<const std::uint8_t> bytes, Seconds t) {
  counters_.add("navdata_datagrams");
  counters_.add("navdata_bytes", bytes.size());
  const auto result = parser_.parse(bytes, packet_);
  if (!result.ok()) {
    counters_.bad_input(to_string(result.error), t, result.detail);
    return false;
  }
  if (!sequence_.accept(packet_)) {
    counters_.bad_input("navdata_out_of_order", t, "sequence " + std::to_string(packet_.sequence) + " not increasing");
    return false;
  }
  counters_.add("navdata_packets");
  if (sequence_.restarted()) counters_.add("navdata_sequence_restarts");
  sample_from_packet(packet_, t, sample_);
  if (handler_) handler_(sample_, packet_);
  return true;
}

void VideoReceiver::bytes(std::span<const std::uint8_t> bytes, Seconds t) {
  counters_.add("video_bytes", bytes.size());
  demuxer_.feed(bytes);
  PaveFrame pave;
  for (;;) {
    const PaveStatus status = demuxer_.next(pave);
    if (status == PaveStatus::NeedMore) return;
    if (status == PaveStatus::ChunkBuffered) continue;
    if (status != PaveStatus::Frame) {
      counters_.bad_input(to_string(status), t, status == PaveStatus::SkippedJunk
                                                    ? std::to_string(demuxer_.skipped_bytes()) + " bytes skipped"
                                                    : std::string("PaVE header refused, resynchronising"));
      if (status == PaveStatus::SkippedJunk) counters_.add("pave_junk_bytes", demuxer_.skipped_bytes());
      continue;
    }
    counters_.add("video_frames");
    if (pave.header.frame_type == static_cast<std::uint8_t>(PaveFrameType::Idr)) counters_.add("video_keyframes");
    if (pave.header.codec != kPaveCodecH264) {
      counters_.bad_input("pave_not_h264", t, "codec " + std::to_string(pave.header.codec) + ", expected 4 (H.264)");
      continue;
    }
    const std::span<const std::uint8_t> unit = assemble(pave);
    if (unit.empty()) continue;
    if (encoded_) forward(unit, pave.header, t);
    // Reuse the picture buffer unless a listener kept a reference to the last frame.
    if (frame_.bgr.u && frame_.bgr.u->refcount > 1) frame_.bgr.release();
    const DecodeStatus decoded = decoder_.decode(unit, frame_.bgr);
    if (decoded == DecodeStatus::Error) {
      counters_.bad_input(to_string(decoded), t, "frame " + std::to_string(pave.header.frame_number));
      continue;
    }
    if (decoded != DecodeStatus::Decoded) {
      counters_.add(to_string(decoded));
      continue;
    }
    counters_.add("video_decoded");
    frame_.t = t;
    frame_.camera = camera_;
    frame_.frame_number = pave.header.frame_number;
    if (handler_) handler_(frame_);
  }
}

std::span<const std::uint8_t> VideoReceiver::assemble(const PaveFrame& pave) {
  const PaveHeader& h = pave.header;
  if (h.total_slices <= 1) return pave.payload;
  // One access unit in several packets: joined in order; a gap drops the frame (the decoder then
  // conceals or waits for the next IDR). `slices_` keeps its capacity: no allocation per frame.
  if (h.slice_index == 0) {
    slices_.clear();
    slices_frame_ = h.frame_number;
  } else if (slices_next_ != h.slice_index || h.frame_number != slices_frame_) {
    counters_.add("video_slices_orphaned");
    slices_next_ = 0;
    return {};
  }
  slices_.insert(slices_.end(), pave.payload.begin(), pave.payload.end());
  slices_next_ = static_cast<std::uint8_t>(h.slice_index + 1);
  if (slices_next_ < h.total_slices) return {};
  slices_next_ = 0;
  return slices_;
}

void VideoReceiver::forward(std::span<const std::uint8_t> unit, const PaveHeader& h, Seconds t) {
  const bool keyframe = contains_idr(unit);
  forward_seen_idr_ = forward_seen_idr_ || keyframe;
  if (!forward_seen_idr_) return;
  encoded_(EncodedVideo{t, camera_, h.frame_number, keyframe, h.display_width, h.display_height, unit});
}

void VideoReceiver::reset() {
  demuxer_.reset();
  decoder_.reset();
  slices_.clear();
  slices_next_ = 0;
  forward_seen_idr_ = false;
}

}  // namespace labo::ardrone2
