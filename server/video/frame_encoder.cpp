#include "server/video/frame_encoder.hpp"

#include <chrono>
#include <opencv2/imgcodecs.hpp>

#include "server/video/frame_header.hpp"

namespace labo {

FrameEncoder::FrameEncoder(int jpeg_quality, std::size_t pool_size)
    : params_{cv::IMWRITE_JPEG_QUALITY, jpeg_quality}, pool_(pool_size) {
  for (auto& b : pool_) b = std::make_shared<std::string>();
  jpeg_.reserve(256 * 1024);
}

std::shared_ptr<std::string> FrameEncoder::free_buffer() {
  for (auto& b : pool_)
    if (b.use_count() == 1) return b;
  // Every pooled buffer is still on its way to some client: grow the pool (bounded by the clients'
  // one-frame slots, so this settles).
  pool_.push_back(std::make_shared<std::string>());
  return pool_.back();
}

WireFrame FrameEncoder::encode(const cv::Mat& bgr, std::uint32_t frame_number, double capture_unix_ms, CameraId camera) {
  const auto start = std::chrono::steady_clock::now();
  cv::imencode(".jpg", bgr, jpeg_, params_);
  FrameHeader header{frame_number, capture_unix_ms, static_cast<std::uint8_t>(camera), static_cast<std::uint32_t>(jpeg_.size())};
  auto buffer = free_buffer();
  buffer->resize(FrameHeader::kSize + jpeg_.size());
  header.write(buffer->data());
  std::memcpy(buffer->data() + FrameHeader::kSize, jpeg_.data(), jpeg_.size());
  last_encode_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return WireFrame{frame_number, capture_unix_ms, camera, buffer};
}

}  // namespace labo
