#pragma once
// Passes grey frames through an H.264 encoder and decoder (libx264 via libavcodec: baseline,
// zerolatency, IDR every 15 frames, a bit rate like the AR.Drone 2.0's stream), so benchmark
// sequences carry real compression artefacts. Benchmark-only; the flight path receives frames
// already decoded by drone/ardrone2.
#include <vector>

#include <opencv2/core.hpp>

namespace labo {

// Returns the decoded frames (same count and size, CV_8UC1). Throws std::runtime_error when no
// H.264 encoder is available.
std::vector<cv::Mat> h264_roundtrip(const std::vector<cv::Mat>& frames, double fps, int bitrate_bps);

}  // namespace labo
