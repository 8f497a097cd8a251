#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "drone/ardrone2/link_receiver.hpp"
#include "drone/ardrone2/navdata_builder.hpp"
#include "tests/drone/ardrone2/fixtures.hpp"

using namespace labo;
using namespace labo::ardrone2;

TEST_CASE("link: bad input is counted by kind and logged at most once a second per kind", "[link]") {
  std::vector<std::string> lines;
  Logger logger("test", LogLevel::Info, [&](const std::string& line) { lines.push_back(line); });
  LinkCounters counters(logger);
  std::vector<NavdataSample> samples;
  NavdataReceiver navdata(counters, [&](const NavdataSample& s, const NavdataPacket&) { samples.push_back(s); });

  const auto good = test::demo_packet();  // sequence 4242
  auto bad_cks = good;
  bad_cks[30] ^= 1;
  auto bad_magic = good;
  bad_magic[1] = 0;
  for (int i = 0; i < 50; ++i) {
    const Seconds t = 10.0 + 0.01 * i;  // all within half a second
    CHECK_FALSE(navdata.datagram(bad_cks, t));
    CHECK_FALSE(navdata.datagram(bad_magic, t));
    CHECK_FALSE(navdata.datagram(std::vector<std::uint8_t>(good.begin(), good.begin() + 9), t));
  }
  CHECK(navdata.datagram(good, 11.0));
  CHECK_FALSE(navdata.datagram(good, 11.1));  // same sequence again: out of order
  CHECK(samples.size() == 1);
  CHECK(samples[0].altitude_m == Approx(1.012));
  CHECK(samples[0].pitch_rad > 0);  // theta -2.15 deg (nose down) = LaboDrone pitch > 0
  CHECK(counters.get("navdata_bad_checksum") == 50);
  CHECK(counters.get("navdata_bad_magic") == 50);
  CHECK(counters.get("navdata_truncated") == 50);
  CHECK(counters.get("navdata_out_of_order") == 1);
  CHECK(counters.get("navdata_packets") == 1);
  CHECK(lines.size() == 4);  // one line per kind
  for (int i = 0; i < 3; ++i) navdata.datagram(bad_cks, 12.0 + i * 0.5);
  CHECK(lines.size() == 6);  // at 12.0 and 13.0, not 12.5

  std::vector<VideoFrame> frames;
  VideoReceiver video(counters, [&](const VideoFrame& f) { frames.push_back(f); });
  auto stream = test::video_capture(16);
  video.bytes(std::vector<std::uint8_t>(100, 0x33), 20.0);  // junk before anything
  video.bytes(stream, 20.1);
  CHECK(frames.size() == 16);
  CHECK(counters.get("pave_junk") >= 2);
  CHECK(counters.get("video_keyframes") == 2);
  // Corrupt H.264 after a valid IDR: refused or concealed, never a crash, counted when refused.
  for (std::size_t i = 2000; i < stream.size(); i += 3) stream[i] = static_cast<std::uint8_t>(i * 7);
  video.reset();
  video.bytes(stream, 21.0);
  // The corruption hits PaVE headers too: some frames are lost to resynchronisation, each counted.
  CHECK(counters.get("video_frames") > 16);
  CHECK(counters.get("pave_junk") + counters.get("pave_bad_header_size") + counters.get("pave_payload_too_large") +
            counters.get("h264_decode_error") > 2);
}

TEST_CASE("link: a frame's PaVE slices are joined, decoded, and passed on undecoded from the first IDR", "[link]") {
  Logger logger("test", LogLevel::Warn);
  LinkCounters counters(logger);
  std::vector<EncodedVideo> units;
  std::vector<std::vector<std::uint8_t>> bytes;
  std::vector<std::uint32_t> decoded;
  VideoReceiver video(
      counters, [&](const VideoFrame& f) { decoded.push_back(f.frame_number); },
      [&](const EncodedVideo& u) {
        units.push_back(u);
        bytes.emplace_back(u.annexb.begin(), u.annexb.end());
      });

  // An encoder's stream, each access unit cut in two PaVE packets (slice 0 and 1 of 2), the first
  // frame (the IDR) left out so that the stream starts on P frames.
  H264Encoder encoder({.width = 320, .height = 180, .fps = 30, .gop = 5, .bitrate_kbps = 500});
  PaveWriter writer;
  std::vector<std::uint8_t> stream;
  std::vector<std::vector<std::uint8_t>> sent;
  cv::Mat image(180, 320, CV_8UC3);
  EncodedFrame encoded;
  for (std::uint32_t n = 0; n < 12; ++n) {
    cv::randu(image, 0, 255);
    REQUIRE(encoder.encode(image, encoded));
    sent.push_back(encoded.data);
    if (n == 0) continue;
    const std::size_t half = encoded.data.size() / 2;
    for (std::uint8_t slice = 0; slice < 2; ++slice) {
      PaveHeader h;
      h.frame_number = n;
      h.total_slices = 2;
      h.slice_index = slice;
      h.display_width = 320;
      h.display_height = 180;
      const auto from = encoded.data.begin() + (slice == 0 ? 0 : static_cast<std::ptrdiff_t>(half));
      const auto to = slice == 0 ? encoded.data.begin() + static_cast<std::ptrdiff_t>(half) : encoded.data.end();
      writer.write(h, std::vector<std::uint8_t>(from, to), stream);
    }
  }
  video.bytes(stream, 5.0);
  // Frames 1-4 are P frames before any IDR: held back. Frame 5 is the next IDR.
  REQUIRE(units.size() == 7);
  CHECK(units[0].frame_number == 5);
  CHECK(units[0].keyframe);
  CHECK(units[5].keyframe);  // frame 10
  CHECK_FALSE(units[1].keyframe);
  CHECK(units[0].width == 320);
  CHECK(units[0].t == 5.0);
  for (std::size_t i = 0; i < units.size(); ++i) CHECK(bytes[i] == sent[units[i].frame_number]);
  // The decoder got the joined units too: every frame from the IDR on, none refused.
  CHECK(decoded == std::vector<std::uint32_t>{5, 6, 7, 8, 9, 10, 11});
  CHECK(counters.get("h264_decode_error") == 0);

  // A slice whose first part never came is dropped and counted; a reset waits for the next IDR again.
  units.clear();
  video.reset();
  stream.clear();
  PaveHeader lone;
  lone.frame_number = 40;
  lone.total_slices = 2;
  lone.slice_index = 1;
  writer.write(lone, sent[5], stream);
  video.bytes(stream, 6.0);
  CHECK(units.empty());
  CHECK(counters.get("video_slices_orphaned") == 1);

  // Slices 0 and 2 of 3 with slice 1 lost: the frame is dropped, not joined with a hole.
  stream.clear();
  for (std::uint8_t slice : {0, 2}) {
    PaveHeader h;
    h.frame_number = 41;
    h.total_slices = 3;
    h.slice_index = slice;
    writer.write(h, sent[10], stream);
  }
  video.bytes(stream, 7.0);
  CHECK(units.empty());
  CHECK(counters.get("video_slices_orphaned") == 2);
}
