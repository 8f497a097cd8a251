#include "tests/drone/ardrone2/fixtures.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <opencv2/imgproc.hpp>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/navdata_builder.hpp"
#include "drone/ardrone2/pave.hpp"

namespace labo::test {

using namespace ardrone2;

std::filesystem::path fixture_dir() { return (labo::source_root() / "tests" / "data") / "ardrone2"; }

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::uint8_t> real_bootstrap_packet() {
  return {0x88, 0x77, 0x66, 0x55, 0x10, 0x0c, 0x80, 0x4f, 0x01, 0, 0, 0,
          0, 0, 0, 0, 0xff, 0xff, 0x08, 0x00, 0xa6, 0x02, 0x00, 0x00};
}

std::vector<std::uint8_t> demo_packet() {
  NavdataPacket p;
  p.state = 0x0F800481;  // flying, camera ready, navdata demo, PIC ok, threads on
  p.sequence = 4242;
  p.vision_defined = 1;
  p.set(kTagDemo, "ctrl_state", 0x40000);  // hovering
  p.set(kTagDemo, "vbat_flying_percentage", 76);
  p.set(kTagDemo, "theta", -2150.0);
  p.set(kTagDemo, "phi", 830.0);
  p.set(kTagDemo, "psi", -45250.0);
  p.set(kTagDemo, "altitude", 1012);
  p.set(kTagDemo, "vx", 310.5);
  p.set(kTagDemo, "vy", -12.25);
  p.set(kTagDemo, "vz", 3.0);
  p.add_option(kTagVisionDetect);
  std::vector<std::uint8_t> out;
  NavdataBuilder().build(p, out);
  return out;
}

std::vector<std::uint8_t> full_packet() {
  NavdataPacket p;
  p.state = 0x0F800081;
  p.sequence = 77;
  double v = 0.5;
  for (const auto& spec : navdata_option_specs()) {
    p.add_option(spec.tag);
    for (auto& x : p.option(spec.tag).raw) x = std::fmod(v += 1.0, 120.0);
  }
  p.set(kTagDemo, "ctrl_state", 0x30001);
  p.set(kTagRawMeasures, "vbat_raw", 12250);
  const std::vector<std::uint8_t> body = {1, 2, 3, 4, 5, 6, 7, 8};
  const std::vector<std::vector<std::uint8_t>> extra = {make_raw_option(28, body)};
  std::vector<std::uint8_t> out;
  NavdataBuilder().build(p, out, extra);
  return out;
}

std::vector<std::uint8_t> video_capture(int frames) {
  H264Encoder encoder;
  EncodedFrame ef;
  PaveWriter writer;
  std::vector<std::uint8_t> stream;
  cv::Mat img(360, 640, CV_8UC3);
  for (int i = 0; i < frames; ++i) {
    img.setTo(cv::Scalar(30, 90, 160));
    cv::circle(img, cv::Point(100 + 12 * i, 180), 40, cv::Scalar(250, 250, 250), cv::FILLED);
    encoder.encode(img, ef);
    PaveHeader h;
    h.frame_number = static_cast<std::uint32_t>(i);
    h.timestamp_ms = static_cast<std::uint32_t>(1000 + 33 * i);
    h.frame_type = ef.keyframe ? 1 : 3;
    h.header1_size = ef.sps_size;
    h.header2_size = ef.pps_size;
    h.header_size = i >= frames / 2 ? 68 : 64;  // some firmware sends 68-byte headers
    if (i == 5) {
      for (std::uint8_t b : {'j', 'u', 'n', 'k', 'P', 'a'}) stream.push_back(b);
    }
    writer.write(h, ef.data, stream);
  }
  return stream;
}

}  // namespace labo::test

// Hidden: rewrites the committed fixtures. Run `build/release/tests/test_drone "[.generate]"`.
#include <catch2/catch.hpp>
#include "core/source_tree.hpp"

TEST_CASE("link: generate the ardrone2 fixtures", "[.generate]") {
  using namespace labo::test;
  write_bytes(fixture_dir() / "navdata_bootstrap_real.bin", real_bootstrap_packet());
  write_bytes(fixture_dir() / "navdata_demo.bin", demo_packet());
  write_bytes(fixture_dir() / "navdata_full.bin", full_packet());
  write_bytes(fixture_dir() / "video_capture.bin", video_capture(20));
  SUCCEED();
}
