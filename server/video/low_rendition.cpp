#include "server/video/low_rendition.hpp"

#include <chrono>
#include <stdexcept>

namespace labo::server {

namespace {
// The frame's size, scaled to at most `max_width` wide, both sides even (4:2:0).
cv::Size encoded_size(const cv::Mat& bgr, int max_width) {
  const double scale = bgr.cols > max_width ? static_cast<double>(max_width) / bgr.cols : 1.0;
  const auto even = [](double v) { return std::max(2, static_cast<int>(v / 2) * 2); };
  return {even(bgr.cols * scale), even(bgr.rows * scale)};
}
}  // namespace

LowRendition::LowRendition(LowRenditionSettings settings) : settings_(settings) {
  if (settings.bitrate_kbps <= 0 || settings.fps <= 0 || settings.gop <= 0 || settings.max_width < 16)
    throw std::invalid_argument("LowRendition: bit rate, fps and GOP must be positive, max_width at least 16");
}

bool LowRendition::encode(const VideoFrame& frame, double capture_unix_ms, bool keyframe_wanted, WireAccessUnit& out) {
  if (frame.bgr.empty() || frame.bgr.type() != CV_8UC3) return false;
  const auto start = std::chrono::steady_clock::now();
  const cv::Size size = encoded_size(frame.bgr, settings_.max_width);
  if (!encoder_ || encoder_->settings().width != size.width || encoder_->settings().height != size.height)
    encoder_ = std::make_unique<ardrone2::H264Encoder>(
        ardrone2::H264EncoderSettings{size.width, size.height, settings_.fps, settings_.gop, settings_.bitrate_kbps});
  if (keyframe_wanted) encoder_->request_idr();
  if (!encoder_->encode(frame.bgr, encoded_)) return false;
  const EncodedVideo unit{frame.t, frame.camera, frame.frame_number, encoded_.keyframe, size.width, size.height, encoded_.data};
  out = packer_.pack(unit, capture_unix_ms, Rendition::Low);
  last_encode_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return true;
}

}  // namespace labo::server
