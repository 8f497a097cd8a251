#pragma once
// What a rendered frame goes through before the face pipeline sees it in the face benchmarks: blur,
// sensor noise, then the AR.Drone's video path.
#include <opencv2/core.hpp>
#include <vector>

#include "drone/ardrone2/h264_codec.hpp"
#include "core/camera_model.hpp"

namespace labo::bench {

struct FrameDegradation {
  bool lossy_video = true;        // H.264 round trip through the link's codec
  int video_bitrate_kbps = 1000;  // the AR.Drone 2.0's default video:max_bitrate
};

// Blur, sensor noise, then H.264 (baseline, zero latency, IDR every 15 frames) encoded and decoded in
// process with the link's codec. One degrader is one video: its frames share the codec's state and a
// noise generator seeded by `seed`.
class FrameDegrader {
 public:
  FrameDegrader(const FrameDegradation& d, const PinholeCamera& camera, unsigned seed);
  void apply(double blur_sigma, double noise_sigma, cv::Mat& frame);

 private:
  FrameDegradation degradation_;
  cv::RNG rng_;
  cv::Mat work_, noise_, bgr_, decoded_;
  ardrone2::H264Encoder encoder_;
  ardrone2::H264Decoder decoder_;
  ardrone2::EncodedFrame packet_;
};

// The registration pictures of the benchmarks: `count` consecutive frames of the still head rendered
// in `frontal`, each blurred by 0.5 px, with noise of 2 grey levels and the video path, from one
// video seeded by `seed` (the first is the picture a one-picture registration uses).
std::vector<cv::Mat> degraded_registration_pictures(const cv::Mat& frontal, int count, const FrameDegradation& d,
                                                    const PinholeCamera& camera, unsigned seed);

}  // namespace labo::bench
