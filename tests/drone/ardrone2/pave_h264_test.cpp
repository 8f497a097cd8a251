#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/pave.hpp"

using namespace labo::ardrone2;

namespace {

cv::Mat test_image(int i) {
  cv::Mat img(360, 640, CV_8UC3, cv::Scalar(40, 80, 120));
  cv::rectangle(img, cv::Rect(20 + 8 * i, 40, 120, 90), cv::Scalar(250, 250, 250), cv::FILLED);
  cv::circle(img, cv::Point(400, 200 + 2 * i), 50, cv::Scalar(0, 0, 255), cv::FILLED);
  return img;
}

struct Demuxed {
  std::vector<PaveHeader> headers;
  std::vector<std::vector<std::uint8_t>> payloads;
  std::size_t junk = 0, bad_header = 0, too_large = 0;
};

void drain(PaveDemuxer& d, Demuxed& out) {
  PaveFrame f;
  for (;;) {
    const auto s = d.next(f);
    if (s == PaveStatus::NeedMore) return;
    if (s == PaveStatus::Frame) {
      out.headers.push_back(f.header);
      out.payloads.emplace_back(f.payload.begin(), f.payload.end());
    }
    if (s == PaveStatus::SkippedJunk) out.junk += d.skipped_bytes();
    if (s == PaveStatus::BadHeaderSize) ++out.bad_header;
    if (s == PaveStatus::PayloadTooLarge) ++out.too_large;
  }
}

}  // namespace

TEST_CASE("link: PaVE header written and parsed back, 64 and 68 bytes", "[link]") {
  for (std::uint16_t hs : {64, 68}) {
    PaveHeader h;
    h.header_size = hs;
    h.frame_number = 77;
    h.timestamp_ms = 1234;
    h.frame_type = 1;
    h.header1_size = 14;
    h.header2_size = 10;
    const std::vector<std::uint8_t> payload = {0, 0, 0, 1, 0x65, 1, 2, 3};
    std::vector<std::uint8_t> stream;
    PaveWriter().write(h, payload, stream);
    CHECK(stream.size() == hs + payload.size());
    PaveDemuxer d;
    d.feed(stream);
    PaveFrame f;
    REQUIRE(d.next(f) == PaveStatus::Frame);
    CHECK(f.header.header_size == hs);
    CHECK(f.header.frame_number == 77);
    CHECK(f.header.timestamp_ms == 1234);
    CHECK(f.header.frame_type == 1);
    CHECK(f.header.header1_size == 14);
    CHECK(f.header.encoded_height == 368);
    CHECK(std::vector<std::uint8_t>(f.payload.begin(), f.payload.end()) == payload);
    CHECK(d.next(f) == PaveStatus::NeedMore);
  }
}

TEST_CASE("link: PaVE stream split at awkward boundaries with junk between frames", "[link]") {
  std::vector<std::uint8_t> stream;
  std::vector<std::vector<std::uint8_t>> payloads;
  std::mt19937 rng(7);
  PaveWriter w;
  for (int i = 0; i < 20; ++i) {
    std::vector<std::uint8_t> payload(1 + rng() % 3000);
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    PaveHeader h;
    h.frame_number = static_cast<std::uint32_t>(i);
    h.header_size = i % 3 == 0 ? 68 : 64;
    if (i % 4 == 1) {  // junk, including a partial signature
      for (std::uint8_t b : {'x', 'P', 'a', 'V', 'y', 'P', 'P', 'a'}) stream.push_back(b);
    }
    w.write(h, payload, stream);
    payloads.push_back(payload);
  }
  for (std::size_t step : {1u, 2u, 3u, 5u, 63u, 64u, 65u, 67u, 4096u}) {
    PaveDemuxer d;
    Demuxed out;
    for (std::size_t pos = 0; pos < stream.size(); pos += step) {
      d.feed(std::span(stream).subspan(pos, std::min(step, stream.size() - pos)));
      drain(d, out);
    }
    INFO("step " << step);
    REQUIRE(out.payloads.size() == payloads.size());
    for (std::size_t i = 0; i < payloads.size(); ++i) {
      CHECK(out.headers[i].frame_number == i);
      CHECK(out.payloads[i] == payloads[i]);
    }
    CHECK(out.junk == 5 * 8);
  }
}

TEST_CASE("link: PaVE refuses a header_size below 64 and oversized payloads, then resyncs", "[link]") {
  std::vector<std::uint8_t> stream;
  PaveWriter w;
  PaveHeader h;
  w.write(h, std::vector<std::uint8_t>(10, 1), stream);
  stream[6] = 20;  // header_size 20 < 64
  const std::size_t second = stream.size();
  w.write(h, std::vector<std::uint8_t>(10, 2), stream);
  stream[second + 8] = 0xFF;  // payload_size huge
  stream[second + 11] = 0x7F;
  h.frame_number = 3;
  w.write(h, std::vector<std::uint8_t>(10, 3), stream);
  PaveDemuxer d(64 * 1024);
  d.feed(stream);
  Demuxed out;
  drain(d, out);
  CHECK(out.bad_header == 1);
  CHECK(out.too_large == 1);
  REQUIRE(out.payloads.size() == 1);
  CHECK(out.headers[0].frame_number == 3);
  CHECK(d.buffered_bytes() <= 3);
}

TEST_CASE("link: PaVE chunks of one frame are joined", "[link]") {
  std::vector<std::uint8_t> stream;
  PaveWriter w;
  PaveHeader h;
  h.frame_number = 5;
  h.total_chunks = 3;
  for (std::uint8_t c = 0; c < 3; ++c) {
    h.chunk_index = c;
    w.write(h, std::vector<std::uint8_t>(4, c), stream);
  }
  PaveDemuxer d;
  d.feed(stream);
  PaveFrame f;
  CHECK(d.next(f) == PaveStatus::ChunkBuffered);
  CHECK(d.next(f) == PaveStatus::ChunkBuffered);
  REQUIRE(d.next(f) == PaveStatus::Frame);
  CHECK(f.payload.size() == 12);
  CHECK(f.payload[11] == 2);
  CHECK(f.header.frame_number == 5);
}

TEST_CASE("link: libx264 frames through PaVE decode back at the right size and count", "[link]") {
  H264Encoder enc;
  std::vector<std::uint8_t> stream;
  PaveWriter w;
  int keyframes = 0;
  EncodedFrame ef;
  const int n = 32;
  for (int i = 0; i < n; ++i) {
    REQUIRE(enc.encode(test_image(i), ef));
    if (i % 15 == 0) {
      CHECK(ef.keyframe);
      CHECK(contains_idr(ef.data));
      CHECK(ef.sps_size > 4);
      CHECK(ef.pps_size > 4);
      CHECK(ef.data[ef.sps_size == 0 ? 0 : 4] == 0x67);  // SPS first, in band
      CHECK(ef.data[5] == 66);  // profile_idc 66: Baseline
    } else {
      CHECK_FALSE(ef.keyframe);
    }
    keyframes += ef.keyframe;
    PaveHeader h;
    h.frame_number = static_cast<std::uint32_t>(i);
    h.frame_type = ef.keyframe ? 1 : 3;
    h.header1_size = ef.sps_size;
    h.header2_size = ef.pps_size;
    w.write(h, ef.data, stream);
  }
  CHECK(keyframes == 3);
  // Start the receiver mid-GOP: it must skip frames until the IDR of frame 15.
  PaveDemuxer d;
  H264Decoder dec;
  cv::Mat bgr;
  int decoded = 0, waited = 0, errors = 0;
  const std::size_t chunk = 1000;
  for (std::size_t pos = 0; pos < stream.size(); pos += chunk) {
    d.feed(std::span(stream).subspan(pos, std::min(chunk, stream.size() - pos)));
    PaveFrame f;
    PaveStatus s;
    while ((s = d.next(f)) != PaveStatus::NeedMore) {
      REQUIRE(s == PaveStatus::Frame);
      if (f.header.frame_number < 3) continue;  // joined late
      const auto r = dec.decode(f.payload, bgr);
      if (r == DecodeStatus::Decoded) {
        ++decoded;
        CHECK(bgr.cols == 640);
        CHECK(bgr.rows == 360);
        if (f.header.frame_number == 20) {
          // Decoded picture close to the source (lossy, so a tolerance).
          cv::Mat diff;
          cv::absdiff(bgr, test_image(20), diff);
          CHECK(cv::mean(diff)[0] < 6.0);
        }
      }
      waited += r == DecodeStatus::WaitingForIdr;
      errors += r == DecodeStatus::Error;
    }
  }
  CHECK(waited == 12);  // frames 3..14
  CHECK(decoded == n - 15);
  CHECK(errors == 0);
}

TEST_CASE("link: corrupt H.264 is reported, never crashes, and the next IDR recovers", "[link]") {
  H264Encoder enc;
  H264Decoder dec;
  EncodedFrame ef;
  cv::Mat bgr;
  std::mt19937 rng(3);
  int errors_or_empty = 0, decoded_after = 0;
  for (int i = 0; i < 30; ++i) {
    REQUIRE(enc.encode(test_image(i), ef));
    if (i >= 1 && i < 15) {
      for (std::size_t k = 4; k < ef.data.size(); k += 7) ef.data[k] = static_cast<std::uint8_t>(rng());
    }
    const auto r = dec.decode(ef.data, bgr);
    if (i >= 1 && i < 15 && r != DecodeStatus::Decoded) ++errors_or_empty;
    if (i >= 15 && r == DecodeStatus::Decoded) ++decoded_after;
  }
  CHECK(errors_or_empty > 0);
  CHECK(decoded_after == 15);
  std::vector<std::uint8_t> garbage(5000);
  for (auto& b : garbage) b = static_cast<std::uint8_t>(rng());
  garbage[0] = 0, garbage[1] = 0, garbage[2] = 1, garbage[3] = 0x65;  // claims an IDR slice
  H264Decoder fresh;
  const auto r = fresh.decode(garbage, bgr);
  CHECK(r != DecodeStatus::Decoded);
}

namespace {
// A detailed picture that moves every frame, so that the bit rate, not the content, limits the size.
cv::Mat busy_image(int i) {
  static const cv::Mat texture = [] {
    cv::Mat t(400, 700, CV_8UC3);
    cv::randu(t, cv::Scalar::all(0), cv::Scalar::all(255));
    cv::GaussianBlur(t, t, cv::Size(3, 3), 0.7);
    return t;
  }();
  return texture(cv::Rect(i % 50, (2 * i) % 40, 640, 360)).clone();
}

// Mean size of the P frames among `count` frames; `keyframes` counts the IDRs.
double mean_p_frame_bytes(H264Encoder& enc, int first, int count, int& keyframes) {
  EncodedFrame ef;
  double bytes = 0;
  int frames = 0;
  for (int i = first; i < first + count; ++i) {
    REQUIRE(enc.encode(busy_image(i), ef));
    if (ef.keyframe) {
      ++keyframes;
    } else {
      bytes += static_cast<double>(ef.data.size());
      ++frames;
    }
  }
  return bytes / frames;
}
}  // namespace

TEST_CASE("link: the H.264 encoder changes its bit rate at run time", "[link]") {
  H264EncoderSettings s;
  s.bitrate_kbps = 1000;
  H264Encoder enc(s);
  int keyframes = 0;
  // Rate control settles over the first GOPs; compare steady states.
  mean_p_frame_bytes(enc, 0, 30, keyframes);
  const double at_1000 = mean_p_frame_bytes(enc, 30, 30, keyframes);
  CHECK(keyframes == 4);  // every 15 frames
  enc.set_bitrate_kbps(4000);
  CHECK(enc.settings().bitrate_kbps == 4000);
  EncodedFrame ef;
  REQUIRE(enc.encode(busy_image(60), ef));
  CHECK(ef.keyframe);  // the re-created encoder starts with an IDR, SPS and PPS in band
  CHECK(ef.sps_size > 4);
  mean_p_frame_bytes(enc, 61, 29, keyframes);
  const double at_4000 = mean_p_frame_bytes(enc, 90, 30, keyframes);
  // 1000 kbit/s at 30 fps is ~4.2 kB per frame, 4000 kbit/s ~16.7 kB (the IDRs take their share).
  CHECK(at_1000 < 4200);
  CHECK(at_4000 > 3.0 * at_1000);
  enc.set_bitrate_kbps(1000);
  mean_p_frame_bytes(enc, 120, 30, keyframes);
  CHECK(mean_p_frame_bytes(enc, 150, 30, keyframes) < 1.3 * at_1000);
  CHECK_THROWS(enc.set_bitrate_kbps(0));
}

TEST_CASE("link: the simulated drone's encoder moves blocks by quarter pixels and deblocks", "[link]") {
  // x264's ultrafast copies blocks by whole pixels and skips the in-loop filter; a hardware baseline
  // encoder does neither, and whole-pixel copies shift a far panel's detail by up to half a pixel per
  // macroblock (docs/ardrone2.md "The simulated drone's encoder"). libx264 states its options in an
  // SEI message of the first access unit.
  H264Encoder enc(H264EncoderSettings{});
  EncodedFrame ef;
  REQUIRE(enc.encode(busy_image(0), ef));
  const std::string unit(ef.data.begin(), ef.data.end());
  const auto options = unit.find("options:");
  REQUIRE(options != std::string::npos);
  const std::string stated = unit.substr(options, 1000);
  INFO(stated);
  CHECK(stated.find(" subme=1 ") != std::string::npos);      // quarter-pel refinement (0: whole pixels)
  CHECK(stated.find(" deblock=1:") != std::string::npos);    // the in-loop deblocking filter
  CHECK(stated.find(" bframes=0 ") != std::string::npos);    // baseline, low delay, as the drone
  CHECK(stated.find(" keyint=15 ") != std::string::npos);
}
