// The Tello's video on UDP 11111: H.264 access units cut into datagrams of 1460 bytes are put back
// together and decoded; junk, lost and oversize data are counted and never crash the receiver.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "core/log.hpp"
#include "drone/ardrone2/h264_codec.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_receivers.hpp"

using namespace labo;
using namespace labo::tello;

namespace {

using Bytes = std::vector<std::uint8_t>;

// `count` access units of a moving square, 320x240 (small: the tests are about framing).
std::vector<Bytes> encoded_units(int count, int gop = 10) {
  ardrone2::H264Encoder encoder({.width = 320, .height = 240, .fps = 30, .gop = gop, .bitrate_kbps = 2000});
  std::vector<Bytes> units;
  cv::Mat image(240, 320, CV_8UC3);
  ardrone2::EncodedFrame frame;
  for (int i = 0; i < count; ++i) {
    image.setTo(cv::Scalar(30, 60, 200));
    cv::randu(image(cv::Rect(0, 150, 320, 90)), cv::Scalar::all(0), cv::Scalar::all(255));  // detail: kB-sized units
    cv::rectangle(image, cv::Rect(10 + 5 * i, 50, 40, 40), cv::Scalar(255, 255, 255), cv::FILLED);
    REQUIRE(encoder.encode(image, frame));
    units.push_back(frame.data);
  }
  return units;
}

// The unit cut as a Tello sends it: datagrams of `size` bytes, the last one shorter.
std::vector<Bytes> datagrams_of(const Bytes& unit, std::size_t size = kTelloVideoDatagramBytes) {
  std::vector<Bytes> out;
  for (std::size_t at = 0; at < unit.size(); at += size)
    out.emplace_back(unit.begin() + static_cast<long>(at), unit.begin() + static_cast<long>(std::min(unit.size(), at + size)));
  return out;
}

struct Collected {
  std::vector<Bytes> units;
  AnnexBAssembler assembler{[this](std::span<const std::uint8_t> u) { units.emplace_back(u.begin(), u.end()); }};
  AnnexBAssembler::Report feed(const Bytes& d) { return assembler.feed(d); }
};

std::uint64_t count(const LinkStatistics& s, const char* kind) {
  const auto it = s.counters.find(kind);
  return it == s.counters.end() ? 0 : it->second;
}

}  // namespace

TEST_CASE("tello: datagrams of 1460 bytes give back the encoder's access units at once", "[tello][video]") {
  const auto units = encoded_units(12);
  Collected c;
  for (std::size_t i = 0; i < units.size(); ++i) {
    for (const auto& d : datagrams_of(units[i])) c.feed(d);
    // A frame's last datagram is shorter than 1460: the unit is out without waiting for the next.
    REQUIRE(c.units.size() == i + 1);
    CHECK(c.units.back() == units[i]);
  }
  CHECK(c.assembler.buffered_bytes() == 0);
}

TEST_CASE("tello: a unit that fills its datagrams exactly ends at the next unit's first NAL", "[tello][video]") {
  const auto units = encoded_units(6);
  Collected c;
  // The first unit (an IDR, several kB) in one datagram of its own size: no shorter datagram ends it.
  REQUIRE(units[0].size() >= kTelloVideoDatagramBytes);
  c.feed(units[0]);
  CHECK(c.units.empty());
  for (std::size_t i = 1; i < units.size(); ++i)
    for (const auto& d : datagrams_of(units[i])) c.feed(d);
  REQUIRE(c.units.size() == units.size());
  for (std::size_t i = 0; i < units.size(); ++i) CHECK(c.units[i] == units[i]);

  // Cut every 7 bytes (start codes and NAL headers split across datagrams), all of them "full": each
  // unit comes out when the next one begins, byte for byte.
  Bytes stream;
  for (const auto& u : units) stream.insert(stream.end(), u.begin(), u.end());
  std::vector<Bytes> out;
  AnnexBAssembler seven([&](std::span<const std::uint8_t> u) { out.emplace_back(u.begin(), u.end()); },
                        kDefaultMaxUnitBytes, 7);
  for (std::size_t at = 0; at < stream.size(); at += 7)
    seven.feed(std::span(stream).subspan(at, std::min<std::size_t>(7, stream.size() - at)));
  REQUIRE(out.size() >= units.size() - 1);
  for (std::size_t i = 0; i + 1 < units.size(); ++i) CHECK(out[i] == units[i]);
}

TEST_CASE("tello: junk on port 11111 is dropped and counted, the stream resynchronises", "[tello][video]") {
  const auto units = encoded_units(8);
  Collected c;
  auto r = c.feed(Bytes{1, 2, 3, 4, 5, 6, 7});  // junk before anything
  CHECK(r.junk_bytes == 7);
  for (const auto& d : datagrams_of(units[0])) c.feed(d);
  r = c.feed(Bytes(100, 0xAB));  // a junk datagram between two frames
  CHECK(r.junk_bytes == 100);
  for (std::size_t i = 1; i < units.size(); ++i)
    for (const auto& d : datagrams_of(units[i])) c.feed(d);
  REQUIRE(c.units.size() == units.size());
  for (std::size_t i = 0; i < units.size(); ++i) CHECK(c.units[i] == units[i]);

  // A unit over the limit is dropped whole; the next start code starts over.
  Collected small;
  AnnexBAssembler limited([&](std::span<const std::uint8_t> u) { small.units.emplace_back(u.begin(), u.end()); }, 2000);
  bool overflow = false;
  for (const auto& u : units)
    for (const auto& d : datagrams_of(u)) overflow = limited.feed(d).overflow || overflow;
  CHECK(overflow);
  for (const auto& u : small.units) CHECK(u.size() <= 2000);
}

TEST_CASE("tello: the video receiver decodes the stream and counts what it refuses", "[tello][video]") {
  ardrone2::LinkCounters counters(Logger("test", LogLevel::Off));
  std::vector<VideoFrame> frames;
  std::vector<EncodedVideo> encoded;  // spans dropped: only the fields are kept
  TelloVideoReceiver receiver(
      counters,
      [&](const VideoFrame& f) {
        VideoFrame copy = f;
        copy.bgr = f.bgr.clone();
        frames.push_back(copy);
      },
      [&](const EncodedVideo& e) {
        CHECK(e.annexb.size() > 0);
        encoded.push_back(e);
        encoded.back().annexb = {};
      });
  const auto units = encoded_units(20, 10);
  // Start mid-stream (a client joining late): frames before the first IDR are not decodable.
  for (std::size_t i = 3; i < units.size(); ++i)
    for (const auto& d : datagrams_of(units[i])) receiver.datagram(d, 0.1 * static_cast<double>(i));
  auto stats = counters.snapshot();
  CHECK(count(stats, "h264_waiting_for_idr") == 7);  // units 3-9; 10 is the next IDR
  REQUIRE(frames.size() == 10);
  CHECK(frames.front().bgr.cols == 320);
  CHECK(frames.front().bgr.rows == 240);
  CHECK(frames.front().camera == CameraId::Bottom);  // 320x240: the downward camera's pictures (downvision)
  CHECK(frames.front().t == Approx(1.0));  // the receive time of the unit's last datagram
  CHECK(frames.back().frame_number == frames.front().frame_number + 9);
  CHECK(count(stats, "video_keyframes") == 1);  // unit 10
  // The undecoded units go on from the first IDR, each before its frame, with the decoder's size.
  REQUIRE(encoded.size() == 10);
  CHECK(encoded.front().keyframe);
  CHECK_FALSE(encoded[1].keyframe);
  CHECK(encoded.front().width == 320);
  CHECK(encoded.front().height == 240);
  CHECK(encoded.front().frame_number == frames.front().frame_number);
  CHECK(encoded.front().t == frames.front().t);

  // Junk datagrams of every size, with start codes in them: counted, no crash, decoding goes on.
  std::mt19937 rng(7);
  for (int i = 0; i < 200; ++i) {
    Bytes junk(1 + rng() % 1460);
    for (auto& b : junk) b = static_cast<std::uint8_t>(rng() % 4 == 0 ? 0 : rng());
    if (junk.size() > 8 && i % 3 == 0) junk[4] = 1;  // 00 00 01 somewhere
    receiver.datagram(junk, 5.0);
  }
  receiver.reset();
  const std::size_t before = frames.size();
  for (const auto& u : units)
    for (const auto& d : datagrams_of(u)) receiver.datagram(d, 6.0);
  CHECK(frames.size() == before + units.size());
  stats = counters.snapshot();
  CHECK(count(stats, "tello_video_junk") > 0);
}
