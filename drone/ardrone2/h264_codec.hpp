#pragma once
// H.264 through FFmpeg. H264Encoder: libx264 via libavcodec, configured like the AR.Drone 2.0's
// stream (Baseline, zero latency, no B-frames, an IDR every 15 frames with SPS/PPS in band, so every
// IDR can start a decoder). H264Decoder: low delay, drops everything before the first IDR, outputs BGR
// through libswscale. Both reuse their buffers: steady-state frames do not allocate.
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

namespace labo::ardrone2 {

struct H264EncoderSettings {
  int width = 640;
  int height = 360;
  int fps = 30;
  int gop = 15;                  // frames between IDRs
  int bitrate_kbps = 1000;       // video:max_bitrate default
};

struct EncodedFrame {
  std::vector<std::uint8_t> data;  // Annex-B access unit
  bool keyframe = false;
  std::uint8_t sps_size = 0;       // with start code, 0 when absent (PaVE header1_size)
  std::uint8_t pps_size = 0;       // with start code, 0 when absent (PaVE header2_size)
  std::int64_t index = 0;          // frames since the encoder was (re)created
};

// Sizes of the SPS and PPS NAL units (start codes included) in an Annex-B access unit.
void find_parameter_sets(std::span<const std::uint8_t> annexb, std::uint8_t& sps_size, std::uint8_t& pps_size);
// True when the access unit holds an IDR slice (NAL type 5).
bool contains_idr(std::span<const std::uint8_t> annexb);

class H264Encoder {
 public:
  explicit H264Encoder(const H264EncoderSettings& settings = {});
  ~H264Encoder();
  H264Encoder(const H264Encoder&) = delete;
  H264Encoder& operator=(const H264Encoder&) = delete;
  H264Encoder(H264Encoder&&) noexcept;
  H264Encoder& operator=(H264Encoder&&) noexcept;

  // Encodes one BGR frame (CV_8UC3, the configured size; other sizes are resized). With
  // zerolatency every input yields its access unit at once; returns false only on an encoder error.
  bool encode(const cv::Mat& bgr, EncodedFrame& out);
  // Changes the target bit rate from the next frame on (AT*CONFIG video:max_bitrate): the encoder is
  // re-created, so the next frame is an IDR (with SPS/PPS) and the GOP cadence restarts there.
  void set_bitrate_kbps(int kbps);
  // The next frame is an IDR (with SPS/PPS), whatever the GOP cadence: a server's re-encode for its
  // viewers gives a new viewer a starting point at once. The cadence stays counted from the start.
  void request_idr();
  const H264EncoderSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

enum class DecodeStatus {
  Decoded,        // `bgr` holds a new frame
  WaitingForIdr,  // dropped: no IDR seen yet
  NoFrame,        // accepted, no picture out yet
  Error,          // corrupt data: the decoder refused it (counted; next IDR recovers)
};
std::string_view to_string(DecodeStatus status);

class H264Decoder {
 public:
  H264Decoder();
  ~H264Decoder();
  H264Decoder(const H264Decoder&) = delete;
  H264Decoder& operator=(const H264Decoder&) = delete;
  H264Decoder(H264Decoder&&) noexcept;
  H264Decoder& operator=(H264Decoder&&) noexcept;

  // One access unit (a PaVE payload). `bgr` is reallocated only when the picture size changes.
  DecodeStatus decode(std::span<const std::uint8_t> access_unit, cv::Mat& bgr);
  // Forget the stream (e.g. camera switch or reconnection): wait for the next IDR.
  void reset();
  int width() const;
  int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace labo::ardrone2
