#include "drone/tello/tello_receivers.hpp"

#include <string>

#include "drone/tello/tello_camera_switch.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo::tello {

TelloStateReceiver::TelloStateReceiver(LinkCounters& counters, Handler handler)
    : counters_(counters), handler_(std::move(handler)) {}

bool TelloStateReceiver::datagram(std::span<const std::uint8_t> bytes, Seconds t) {
  counters_.add("state_datagrams");
  counters_.add("state_bytes", bytes.size());
  const TelloStateParseResult result = parser_.parse(bytes, state_);
  if (!result.ok()) {
    counters_.bad_input(to_string(result.error), t, result.detail);
    return false;
  }
  if (result.unknown_fields > 0) counters_.add("tello_state_unknown_fields", result.unknown_fields);
  counters_.add("state_packets");
  int control_state = 0;
  {
    std::lock_guard lock(phase_mutex_);
    phase_.on_state(state_, t);
    control_state = phase_.control_state();
  }
  sample_from_state(state_, t, ++sequence_, control_state, sample_);
  if (handler_) handler_(sample_, state_);
  return true;
}

void TelloStateReceiver::command_sent(std::string_view command, Seconds t) {
  std::lock_guard lock(phase_mutex_);
  phase_.on_sent(command, t);
}

void TelloStateReceiver::command_finished(const CommandOutcome& outcome, Seconds t) {
  std::lock_guard lock(phase_mutex_);
  phase_.on_outcome(outcome, t);
}

void TelloStateReceiver::sticks(bool centred) {
  std::lock_guard lock(phase_mutex_);
  phase_.on_sticks(centred);
}

int TelloStateReceiver::control_state() const {
  std::lock_guard lock(phase_mutex_);
  return phase_.control_state();
}

int TelloStateReceiver::unexpected_landings() const {
  std::lock_guard lock(phase_mutex_);
  return phase_.unexpected_landings();
}

TelloVideoReceiver::TelloVideoReceiver(LinkCounters& counters, Handler handler, EncodedHandler encoded)
    : counters_(counters), handler_(std::move(handler)), encoded_(std::move(encoded)),
      assembler_([this](std::span<const std::uint8_t> unit) { decode(unit); }) {}

void TelloVideoReceiver::datagram(std::span<const std::uint8_t> bytes, Seconds t) {
  counters_.add("video_datagrams");
  counters_.add("video_bytes", bytes.size());
  t_ = t;
  const AnnexBAssembler::Report report = assembler_.feed(bytes);
  if (report.junk_bytes > 0) {
    counters_.bad_input("tello_video_junk", t, std::to_string(report.junk_bytes) + " bytes before a start code");
    counters_.add("tello_video_junk_bytes", report.junk_bytes);
  }
  if (report.overflow)
    counters_.bad_input("tello_video_unit_too_large", t, "an access unit grew past 1 MiB: dropped, resynchronising");
}

void TelloVideoReceiver::decode(std::span<const std::uint8_t> unit) {
  counters_.add("video_frames");
  const bool keyframe = ardrone2::contains_idr(unit);
  if (keyframe) counters_.add("video_keyframes");
  // Reuse the picture buffer unless a listener kept a reference to the last frame.
  if (frame_.bgr.u && frame_.bgr.u->refcount > 1) frame_.bgr.release();
  const ardrone2::DecodeStatus decoded = decoder_.decode(unit, frame_.bgr);
  const std::uint32_t number = frame_number_++;
  forward_seen_idr_ = forward_seen_idr_ || keyframe;
  if (encoded_ && forward_seen_idr_)
    encoded_(EncodedVideo{t_, camera_of(decoder_.width(), decoder_.height()), number, keyframe, decoder_.width(), decoder_.height(), unit});
  if (decoded == ardrone2::DecodeStatus::Error) {
    counters_.bad_input(to_string(decoded), t_, "access unit of " + std::to_string(unit.size()) + " bytes");
    return;
  }
  if (decoded != ardrone2::DecodeStatus::Decoded) {
    counters_.add(to_string(decoded));
    return;
  }
  counters_.add("video_decoded");
  frame_.t = t_;
  frame_.camera = camera_of(frame_.bgr.cols, frame_.bgr.rows);
  frame_.frame_number = number;
  if (handler_) handler_(frame_);
}

// The stream carries one camera at a time; the downward camera's pictures are its own size.
CameraId TelloVideoReceiver::camera_of(int width, int height) {
  return width == kDownvisionWidth && height == kDownvisionHeight ? CameraId::Bottom : CameraId::Front;
}

void TelloVideoReceiver::reset() {
  assembler_.reset();
  decoder_.reset();
  forward_seen_idr_ = false;
}

}  // namespace labo::tello
