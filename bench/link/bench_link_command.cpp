#include "bench/link/bench_link_command.hpp"

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "drone/ardrone2/at_command.hpp"
#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/navdata_builder.hpp"
#include "drone/ardrone2/navdata_parser.hpp"
#include "drone/ardrone2/pave.hpp"
#include "drone/ardrone2/wire_signs.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_state.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo::bench {

using namespace ardrone2;

namespace {

using BenchClock = std::chrono::steady_clock;

// Mean time per call in microseconds over `n` calls.
template <typename Fn>
double time_us(int n, Fn fn) {
  const auto start = BenchClock::now();
  for (int i = 0; i < n; ++i) fn(i);
  return std::chrono::duration<double, std::micro>(BenchClock::now() - start).count() / n;
}

NavdataPacket full_packet() {
  NavdataPacket p;
  for (const auto& spec : navdata_option_specs()) p.add_option(spec.tag);
  p.set(kTagDemo, "theta", 1500.0);
  return p;
}

cv::Mat scene(int i, int width = 640, int height = 360) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(60, 90, 120));
  cv::randu(img(cv::Rect(0, 0, width, height / 3)), cv::Scalar::all(0), cv::Scalar::all(255));  // texture
  cv::circle(img, cv::Point(50 + 5 * (i % 100), 2 * height / 3), height / 7, cv::Scalar(255, 255, 255), cv::FILLED);
  return img;
}

// The Tello's stages: its state string (parsed and converted by the link, written by the emulator),
// the reassembly of its 1460-byte video datagrams, H.264 at its 960x720.
void bench_tello(int frames, nlohmann::json& out) {
  tello::TelloState state;
  state.has_mission_pad = true;
  state.yaw_deg = -90;
  state.tof_cm = 98;
  state.baro_cm = -57.14;
  state.agz_mg = -996;
  std::string text;
  out["tello_state_format_us"] = time_us(50000, [&](int i) {
    state.time_s = i % 1000;
    tello::format_tello_state(state, text);
  });
  out["tello_state_bytes"] = text.size();
  tello::TelloStateParser parser;
  tello::TelloState parsed;
  NavdataSample sample;
  out["tello_state_parse_us"] = time_us(50000, [&](int i) {
    parser.parse(text, parsed);
    tello::sample_from_state(parsed, 0.0, static_cast<std::uint32_t>(i), 4, sample);
  });

  H264Encoder h264({.width = 960, .height = 720, .fps = 30, .gop = 30, .bitrate_kbps = 2000});
  EncodedFrame ef;
  std::vector<std::vector<std::uint8_t>> units;
  std::vector<cv::Mat> images;
  for (int i = 0; i < frames; ++i) images.push_back(scene(i, 960, 720));
  out["tello_h264_encode_960x720_ms"] = time_us(frames, [&](int i) {
    h264.encode(images[static_cast<std::size_t>(i)], ef);
    units.push_back(ef.data);
  }) / 1000.0;
  std::size_t stream_bytes = 0, assembled = 0;
  for (const auto& u : units) stream_bytes += u.size();
  tello::AnnexBAssembler assembler([&](std::span<const std::uint8_t>) { ++assembled; });
  const double assemble_us = time_us(20, [&](int) {
    for (const auto& u : units)
      for (std::size_t at = 0; at < u.size(); at += tello::kTelloVideoDatagramBytes)
        assembler.feed(std::span(u).subspan(at, std::min(tello::kTelloVideoDatagramBytes, u.size() - at)));
  });
  out["tello_annexb_mb_per_s"] = static_cast<double>(stream_bytes) / assemble_us;
  out["tello_assembled_units"] = assembled / 20;
  H264Decoder decoder;
  cv::Mat bgr;
  int decoded = 0;
  out["tello_h264_decode_bgr_960x720_ms"] = time_us(static_cast<int>(units.size()), [&](int i) {
    decoded += decoder.decode(units[static_cast<std::size_t>(i)], bgr) == DecodeStatus::Decoded;
  }) / 1000.0;
  out["tello_decoded"] = decoded;
}

}  // namespace

const CommandSpec& bench_link_command_spec() {
  static const CommandSpec spec{"bench link", "",
                                "Time the link stages: AR.Drone AT encode, navdata parse/build, PaVE demux, H.264 "
                                "encode/decode; Tello state parse/format, Annex-B reassembly, H.264 at 960x720 "
                                "(JSON, per call).",
                                {{"--frames", "N", "video frames to encode and decode (default 150)"}},
                                0,
                                0};
  return spec;
}

int run_bench_link_command(const ParsedArgs& args) {
  const int frames = args.integer_or("--frames", 150, 15, 100000);
  nlohmann::json out;

  AtCommandEncoder encoder;
  std::string at;
  at.reserve(1024);
  out["at_tick_us"] = time_us(100000, [&](int i) {
    at.clear();
    encoder.ref(at, true, false);
    encoder.pcmd(at, move_to_wire(MoveCommand{0.1, 0.2 * (i % 3), 0.0, -0.1}));
  });

  const NavdataPacket full = full_packet();
  std::vector<std::uint8_t> bytes;
  NavdataBuilder builder;
  out["navdata_build_full_us"] = time_us(20000, [&](int) { builder.build(full, bytes); });
  out["navdata_full_bytes"] = bytes.size();
  NavdataParser parser;
  NavdataPacket parsed;
  NavdataSample sample;
  out["navdata_parse_full_us"] = time_us(20000, [&](int) {
    parser.parse(bytes, parsed);
    sample_from_packet(parsed, 0.0, sample);
  });
  NavdataPacket demo;
  demo.add_option(kTagDemo);
  demo.add_option(kTagVisionDetect);
  builder.build(demo, bytes);
  out["navdata_parse_demo_us"] = time_us(50000, [&](int) {
    parser.parse(bytes, parsed);
    sample_from_packet(parsed, 0.0, sample);
  });

  H264Encoder h264;
  EncodedFrame ef;
  PaveWriter writer;
  std::vector<std::uint8_t> stream;
  std::vector<cv::Mat> images;
  for (int i = 0; i < frames; ++i) images.push_back(scene(i));
  out["h264_encode_ms"] = time_us(frames, [&](int i) {
    h264.encode(images[static_cast<std::size_t>(i)], ef);
    PaveHeader h;
    h.frame_number = static_cast<std::uint32_t>(i);
    h.frame_type = ef.keyframe ? 1 : 3;
    writer.write(h, ef.data, stream);
  }) / 1000.0;
  out["video_stream_bytes"] = stream.size();

  const int repeats = 20;
  std::size_t demuxed = 0;
  const double demux_us = time_us(repeats, [&](int) {
    PaveDemuxer demuxer;
    PaveFrame f;
    demuxed = 0;
    for (std::size_t pos = 0; pos < stream.size(); pos += 1460) {  // TCP-segment-sized reads
      demuxer.feed(std::span(stream).subspan(pos, std::min<std::size_t>(1460, stream.size() - pos)));
      for (PaveStatus st; (st = demuxer.next(f)) != PaveStatus::NeedMore;) demuxed += st == PaveStatus::Frame;
    }
  });
  out["pave_demux_mb_per_s"] = static_cast<double>(stream.size()) / demux_us;  // bytes per us = MB/s
  out["pave_demuxed_frames"] = demuxed;

  // Decode the PaVE payloads.
  PaveDemuxer demuxer;
  demuxer.feed(stream);
  std::vector<std::vector<std::uint8_t>> units;
  PaveFrame f;
  while (demuxer.next(f) == PaveStatus::Frame) units.emplace_back(f.payload.begin(), f.payload.end());
  H264Decoder decoder;
  cv::Mat bgr;
  int decoded = 0;
  out["h264_decode_bgr_ms"] = time_us(static_cast<int>(units.size()), [&](int i) {
    decoded += decoder.decode(units[static_cast<std::size_t>(i)], bgr) == DecodeStatus::Decoded;
  }) / 1000.0;
  out["frames"] = frames;
  out["decoded"] = decoded;
  bench_tello(frames, out);
  std::cout << out.dump(2) << "\n";
  return decoded == frames && demuxed == static_cast<std::size_t>(frames) && out["tello_decoded"] == frames ? 0 : 1;
}

}  // namespace labo::bench
