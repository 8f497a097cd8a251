#include "bench/planar/h264_roundtrip.hpp"

#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace labo::bench {

ardrone2::H264EncoderSettings drone_stream_settings(cv::Size size, int fps, int bitrate_kbps) {
  ardrone2::H264EncoderSettings s;  // the GOP and everything else as SimDroneLink leaves them
  s.width = size.width;
  s.height = size.height;
  s.fps = fps;
  s.bitrate_kbps = bitrate_kbps;
  return s;
}

std::vector<cv::Mat> h264_roundtrip(const std::vector<cv::Mat>& frames, const ardrone2::H264EncoderSettings& settings) {
  for (const cv::Mat& f : frames) {
    if (f.type() != CV_8UC1 || f.cols != settings.width || f.rows != settings.height) {
      throw std::invalid_argument("h264 round trip: frames must be CV_8UC1 of the encoder's size " +
                                  std::to_string(settings.width) + "x" + std::to_string(settings.height));
    }
  }
  ardrone2::H264Encoder encoder(settings);
  ardrone2::H264Decoder decoder;
  ardrone2::EncodedFrame packet;
  cv::Mat bgr, decoded;
  std::vector<cv::Mat> out;
  out.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    cv::cvtColor(frames[i], bgr, cv::COLOR_GRAY2BGR);
    if (!encoder.encode(bgr, packet)) throw std::runtime_error("h264 round trip: encoder error at frame " + std::to_string(i));
    const ardrone2::DecodeStatus status = decoder.decode(packet.data, decoded);
    if (status != ardrone2::DecodeStatus::Decoded) {
      throw std::runtime_error("h264 round trip: frame " + std::to_string(i) + ": " + std::string(ardrone2::to_string(status)));
    }
    cv::Mat& grey = out.emplace_back();
    cv::cvtColor(decoded, grey, cv::COLOR_BGR2GRAY);
  }
  return out;
}

}  // namespace labo::bench
