#pragma once
// The shared low rendition: the decoded frames re-encoded once, at a lower bit rate, for every H.264
// viewer whose link cannot carry the drone's own stream (video/rendition_policy.hpp). One libx264
// encoder (Baseline, zero latency, as the drone's stream, so the page decodes both alike) for all
// such viewers, never one per viewer; it runs only while one of them needs it and is released
// otherwise, so a server without slow viewers pays nothing. Frames wider than `max_width` are scaled
// down (a Tello's 960x720 to 640x480). Each unit carries its source frame's number and capture time,
// so that its overlay geometry and the latency the page shows are the source frame's. Called from
// one thread (the runtime's video thread).
#include <cstdint>
#include <memory>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/drone_link.hpp"
#include "server/lab/flight_service.hpp"
#include "server/video/access_unit_wire.hpp"

namespace labo::server {

struct LowRenditionSettings {
  int bitrate_kbps = 1000;
  int fps = 30;
  int gop = 30;         // frames between scheduled IDRs; a new viewer asks for one at once
  int max_width = 640;
};

class LowRendition {
 public:
  explicit LowRendition(LowRenditionSettings settings = {});

  // The frame encoded into `out` (a pooled buffer shared by every low viewer); false when the
  // encoder failed. Starts the encoder when it is not running (its first unit an IDR);
  // `keyframe_wanted` makes this unit an IDR.
  bool encode(const VideoFrame& frame, double capture_unix_ms, bool keyframe_wanted, WireAccessUnit& out);
  // Nobody needs the rendition: the encoder and its buffers go.
  void stop() { encoder_.reset(); }
  bool running() const { return encoder_ != nullptr; }
  const LowRenditionSettings& settings() const { return settings_; }
  double last_encode_ms() const { return last_encode_ms_; }

 private:
  LowRenditionSettings settings_;
  std::unique_ptr<ardrone2::H264Encoder> encoder_;
  ardrone2::EncodedFrame encoded_;
  AccessUnitPacker packer_;
  double last_encode_ms_ = 0;
};

}  // namespace labo::server
