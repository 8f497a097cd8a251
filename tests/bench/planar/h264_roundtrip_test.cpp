#include <catch2/catch.hpp>

#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "drone/ardrone2/h264_codec.hpp"
#include "bench/planar/h264_roundtrip.hpp"
#include "bench/planar/synthetic_scene.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

// A textured scene panning 1.5 px per frame (so P-frames carry motion vectors), 640x360.
std::vector<cv::Mat> panning_frames(int count) {
  const cv::Mat wall = make_clutter_background(cv::Size(800, 400), 3);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < count; ++i) {
    const cv::Matx23d shift(1, 0, -1.5 * i, 0, 1, -0.5 * i);
    cv::Mat f;
    cv::warpAffine(wall, f, shift, cv::Size(640, 360), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    frames.push_back(f);
  }
  return frames;
}

double mean_abs_difference(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += cv::norm(a[i], b[i], cv::NORM_L1) / static_cast<double>(a[i].total());
  return sum / static_cast<double>(a.size());
}

}  // namespace

TEST_CASE("planar: the bench's H.264 round trip is the simulated drone's stream, frame for frame") {
  const std::vector<cv::Mat> frames = panning_frames(20);
  const ardrone2::H264EncoderSettings settings = drone_stream_settings(cv::Size(640, 360), 30, 1000);
  CHECK(settings.gop == ardrone2::H264EncoderSettings{}.gop);  // the sim link's GOP
  const std::vector<cv::Mat> decoded = h264_roundtrip(frames, settings);
  REQUIRE(decoded.size() == frames.size());
  // What SimDroneLink does with a frame (BGR in, H264Encoder, H264Decoder, BGR out) and the flight
  // path's grey conversion after it.
  ardrone2::H264Encoder encoder(settings);
  ardrone2::H264Decoder decoder;
  ardrone2::EncodedFrame packet;
  cv::Mat bgr, out, grey;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    cv::cvtColor(frames[i], bgr, cv::COLOR_GRAY2BGR);
    REQUIRE(encoder.encode(bgr, packet));
    REQUIRE(decoder.decode(packet.data, out) == ardrone2::DecodeStatus::Decoded);
    cv::cvtColor(out, grey, cv::COLOR_BGR2GRAY);
    INFO("frame " << i);
    REQUIRE(decoded[i].type() == CV_8UC1);
    CHECK(cv::norm(decoded[i], grey, cv::NORM_INF) == 0);
  }
  // Lossy, and less so at a higher bit rate.
  const double loss_1000 = mean_abs_difference(decoded, frames);
  const double loss_4000 = mean_abs_difference(h264_roundtrip(frames, drone_stream_settings(cv::Size(640, 360), 30, 4000)), frames);
  CHECK(loss_1000 > 0.5);
  CHECK(loss_4000 < loss_1000);
}

TEST_CASE("planar: the H.264 round trip refuses frames that are not grey or not the encoder's size") {
  const ardrone2::H264EncoderSettings settings = drone_stream_settings(cv::Size(640, 360), 30, 1000);
  CHECK_THROWS_AS(h264_roundtrip({cv::Mat(360, 640, CV_8UC3, cv::Scalar::all(0))}, settings), std::invalid_argument);
  CHECK_THROWS_AS(h264_roundtrip({cv::Mat(240, 320, CV_8UC1, cv::Scalar(0))}, settings), std::invalid_argument);
  CHECK(h264_roundtrip({}, settings).empty());
}
