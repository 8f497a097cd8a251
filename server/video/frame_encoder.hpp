#pragma once
// JPEG-encodes annotated frames into wire messages (header + JPEG), in pooled buffers
// (WireBufferPool): steady-state encoding does not allocate.
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "server/lab/flight_service.hpp"
#include "server/video/wire_buffer_pool.hpp"

namespace labo::server {

class FrameEncoder {
 public:
  explicit FrameEncoder(int jpeg_quality, std::size_t pool_size = 8);
  WireFrame encode(const cv::Mat& bgr, std::uint32_t frame_number, double capture_unix_ms, CameraId camera);
  double last_encode_ms() const { return last_encode_ms_; }

 private:
  std::vector<int> params_;
  std::vector<std::uint8_t> jpeg_;
  WireBufferPool pool_;
  double last_encode_ms_ = 0;
};

}  // namespace labo::server
