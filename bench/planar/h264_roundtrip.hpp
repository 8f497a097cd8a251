#pragma once
// Passes grey frames through H.264 exactly as the simulated drone streams them: drone/ardrone2's
// H264Encoder (the settings of SimDroneLink and ArdroneEmulator: libx264 ultrafast, Baseline,
// zerolatency, no scene-cut keyframes, an IDR every 15 frames) and H264Decoder, the grey frame fed as
// BGR and the decoded BGR turned back to grey as the flight path does (localization/fusion/lab_pipelines.cpp).
// Benchmark-only; in flight drone/ardrone2 decodes the stream itself.
#include <vector>

#include <opencv2/core.hpp>

#include "drone/ardrone2/h264_codec.hpp"

namespace labo::bench {

// The encoder settings of a simulated drone's stream for frames of `size` at `fps` and `bitrate_kbps`.
ardrone2::H264EncoderSettings drone_stream_settings(cv::Size size, int fps, int bitrate_kbps);

// Returns the decoded frames (same count and size, CV_8UC1) of `frames` (CV_8UC1, one size) encoded
// with `settings`. Throws std::invalid_argument on bad frames or settings, std::runtime_error when the
// codec fails.
std::vector<cv::Mat> h264_roundtrip(const std::vector<cv::Mat>& frames, const ardrone2::H264EncoderSettings& settings);

}  // namespace labo::bench
