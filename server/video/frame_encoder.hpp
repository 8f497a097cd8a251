#pragma once
// JPEG-encodes annotated frames into wire messages (header + JPEG). Wire buffers come from a small
// pool and are reused once every client has let go of them, so steady-state encoding does not
// allocate: a buffer still held by a slow client is simply skipped.
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "server/lab/flight_service.hpp"

namespace labo {

class FrameEncoder {
 public:
  explicit FrameEncoder(int jpeg_quality, std::size_t pool_size = 8);
  WireFrame encode(const cv::Mat& bgr, std::uint32_t frame_number, double capture_unix_ms, CameraId camera);
  double last_encode_ms() const { return last_encode_ms_; }

 private:
  std::shared_ptr<std::string> free_buffer();
  std::vector<int> params_;
  std::vector<std::uint8_t> jpeg_;
  std::vector<std::shared_ptr<std::string>> pool_;
  double last_encode_ms_ = 0;
};

}  // namespace labo
