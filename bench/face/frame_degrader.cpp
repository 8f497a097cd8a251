#include "bench/face/frame_degrader.hpp"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <stdexcept>

namespace labo::bench {

namespace {
ardrone2::H264EncoderSettings encoder_settings(const FrameDegradation& d, const PinholeCamera& camera) {
  ardrone2::H264EncoderSettings s;
  s.width = camera.width();
  s.height = camera.height();
  s.bitrate_kbps = d.video_bitrate_kbps;
  return s;
}
}  // namespace

FrameDegrader::FrameDegrader(const FrameDegradation& d, const PinholeCamera& camera, unsigned seed)
    : degradation_(d), rng_(seed), encoder_(encoder_settings(d, camera)) {}

void FrameDegrader::apply(double blur_sigma, double noise_sigma, cv::Mat& frame) {
  if (blur_sigma > 0) cv::GaussianBlur(frame, frame, cv::Size(), blur_sigma);
  frame.convertTo(work_, CV_16S);
  noise_.create(frame.size(), CV_16S);
  rng_.fill(noise_, cv::RNG::NORMAL, 0, noise_sigma);
  work_ += noise_;
  work_.convertTo(frame, CV_8U);  // saturates
  if (degradation_.lossy_video) {
    cv::cvtColor(frame, bgr_, cv::COLOR_GRAY2BGR);
    if (!encoder_.encode(bgr_, packet_)) throw std::runtime_error("face bench: H.264 encoder error");
    if (decoder_.decode(packet_.data, decoded_) != ardrone2::DecodeStatus::Decoded) {
      throw std::runtime_error("face bench: H.264 decoder gave no picture");
    }
    cv::cvtColor(decoded_, frame, cv::COLOR_BGR2GRAY);
  }
}

std::vector<cv::Mat> degraded_registration_pictures(const cv::Mat& frontal, int count, const FrameDegradation& d,
                                                    const PinholeCamera& camera, unsigned seed) {
  FrameDegrader degrader(d, camera, seed);
  std::vector<cv::Mat> pictures;
  for (int k = 0; k < std::max(count, 1); ++k) {
    cv::Mat pic = frontal.clone();
    degrader.apply(0.5, 2.0, pic);
    pictures.push_back(std::move(pic));
  }
  return pictures;
}

}  // namespace labo::bench
