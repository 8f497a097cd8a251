#include "server/video/frame_encoder.hpp"

#include <chrono>
#include <opencv2/imgcodecs.hpp>

#include "server/video/frame_header.hpp"

namespace labo::server {

FrameEncoder::FrameEncoder(int jpeg_quality, std::size_t pool_size)
    : params_{cv::IMWRITE_JPEG_QUALITY, jpeg_quality}, pool_(pool_size) {
  jpeg_.reserve(256 * 1024);
}

WireFrame FrameEncoder::encode(const cv::Mat& bgr, std::uint32_t frame_number, double capture_unix_ms, CameraId camera) {
  const auto start = std::chrono::steady_clock::now();
  cv::imencode(".jpg", bgr, jpeg_, params_);
  FrameHeader header{frame_number, capture_unix_ms, static_cast<std::uint8_t>(camera), static_cast<std::uint32_t>(jpeg_.size())};
  auto buffer = pool_.acquire();
  buffer->resize(FrameHeader::kSize + jpeg_.size());
  header.write(buffer->data());
  std::memcpy(buffer->data() + FrameHeader::kSize, jpeg_.data(), jpeg_.size());
  last_encode_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return WireFrame{frame_number, capture_unix_ms, camera, buffer};
}

}  // namespace labo::server
