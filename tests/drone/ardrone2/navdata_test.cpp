#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "drone/ardrone2/navdata_builder.hpp"
#include "drone/ardrone2/navdata_parser.hpp"

using namespace labo::ardrone2;

namespace {

template <typename T>
void put(std::vector<std::uint8_t>& b, T v) {
  const std::size_t at = b.size();
  b.resize(at + sizeof(T));
  std::memcpy(b.data() + at, &v, sizeof(T));
}

void put_checksum(std::vector<std::uint8_t>& b) {
  std::uint32_t sum = 0;
  for (auto x : b) sum += x;
  put<std::uint16_t>(b, 0xFFFF);
  put<std::uint16_t>(b, 8);
  put<std::uint32_t>(b, sum);
}

// A demo packet written byte by byte following the SDK's navdata_demo_t, not through the builder.
std::vector<std::uint8_t> handmade_demo_packet(std::uint32_t magic = 0x55667788) {
  std::vector<std::uint8_t> b;
  put<std::uint32_t>(b, magic);
  put<std::uint32_t>(b, (1u << 0) | (1u << 10) | (1u << 30));
  put<std::uint32_t>(b, 1234);
  put<std::uint32_t>(b, 1);
  put<std::uint16_t>(b, 0);    // tag demo
  put<std::uint16_t>(b, 148);  // size
  put<std::uint32_t>(b, 0x30001);  // flying, minor 1
  put<std::uint32_t>(b, 87);
  put<float>(b, 2500.0f);   // theta mdeg
  put<float>(b, -1000.0f);  // phi
  put<float>(b, 90000.0f);  // psi
  put<std::int32_t>(b, 1234);  // altitude mm
  put<float>(b, 100.0f);
  put<float>(b, -200.0f);
  put<float>(b, 50.0f);
  put<std::uint32_t>(b, 7);
  for (int i = 0; i < 148 - 4 - 40; ++i) b.push_back(0);
  put<std::uint16_t>(b, 1);  // time
  put<std::uint16_t>(b, 8);
  put<std::uint32_t>(b, (12u << 21) | 345678u);
  put<std::uint16_t>(b, 29);  // an unknown (newer firmware) option, skipped by size
  put<std::uint16_t>(b, 10);
  for (int i = 0; i < 6; ++i) b.push_back(0xAB);
  put<std::uint16_t>(b, 26);  // wifi
  put<std::uint16_t>(b, 8);
  put<std::uint32_t>(b, 400);
  put_checksum(b);
  return b;
}

}  // namespace

TEST_CASE("link: navdata option tables match the SDK sizes", "[link]") {
  for (const auto& spec : navdata_option_specs()) {
    std::size_t bytes = kOptionHeaderBytes;
    for (const auto& f : spec.fields) bytes += wire_size(f.type) * f.count;
    INFO(spec.name);
    CHECK(bytes == spec.size);
  }
  CHECK(state_bit_name(0) == "flying");
  CHECK(state_bit_name(6) == "command_ack");
  CHECK(state_bit_name(30) == "com_watchdog");
  CHECK(state_bit_name(31) == "emergency");
}

TEST_CASE("link: navdata packet built byte by byte parses to the right values", "[link]") {
  for (std::uint32_t magic : {0x55667788u, 0x55667789u}) {
    const auto bytes = handmade_demo_packet(magic);
    NavdataPacket p;
    const auto r = NavdataParser().parse(bytes, p);
    INFO(r.detail);
    REQUIRE(r.ok());
    CHECK(p.checksum_ok);
    CHECK(p.sequence == 1234);
    CHECK(p.state_bit(kStateFlying));
    CHECK(p.state_bit(kStateNavdataDemo));
    CHECK(p.state_bit(kStateComWatchdog));
    CHECK_FALSE(p.state_bit(kStateBootstrap));
    REQUIRE(p.has(kTagDemo));
    CHECK(control_state_major(static_cast<std::uint32_t>(p.raw(kTagDemo, "ctrl_state"))) == 3);
    CHECK(p.raw(kTagDemo, "vbat_flying_percentage") == 87);
    CHECK(p.raw(kTagDemo, "theta") == 2500.0);
    CHECK(p.raw(kTagDemo, "phi") == -1000.0);
    CHECK(p.raw(kTagDemo, "psi") == 90000.0);
    CHECK(p.raw(kTagDemo, "altitude") == 1234);
    CHECK(p.raw(kTagDemo, "vy") == -200.0);
    CHECK(p.raw(kTagDemo, "num_frames") == 7);
    REQUIRE(p.has(kTagTime));
    CHECK(navdata_time_seconds(static_cast<std::uint32_t>(p.raw(kTagTime, "time"))) == Approx(12.345678));
    CHECK(p.raw(kTagWifi, "link_quality") == 400);
    REQUIRE(p.unknown.size() == 1);
    CHECK(p.unknown[0].tag == 29);
    CHECK(p.unknown[0].size == 10);
  }
}

TEST_CASE("link: the real bootstrap capture parses", "[link]") {
  // forum.parrot.com topic 4546: 88776655 100c804f 01000000 00000000 ffff0800 a6020000
  const std::vector<std::uint8_t> b = {0x88, 0x77, 0x66, 0x55, 0x10, 0x0c, 0x80, 0x4f, 0x01, 0, 0, 0,
                                       0, 0, 0, 0, 0xff, 0xff, 0x08, 0x00, 0xa6, 0x02, 0x00, 0x00};
  NavdataPacket p;
  const auto r = NavdataParser().parse(b, p);
  INFO(r.detail);
  REQUIRE(r.ok());
  CHECK(p.state_bit(kStateBootstrap));
  CHECK(p.sequence == 1);
}

TEST_CASE("link: navdata builder round trip of every option", "[link]") {
  NavdataPacket in;
  in.state = 0x0F000001;
  in.sequence = 99;
  double v = 1;
  for (const auto& spec : navdata_option_specs()) {
    in.add_option(spec.tag);
    for (auto& x : in.option(spec.tag).raw) x = std::fmod(v++, 200.0);  // fits every wire type
  }
  std::vector<std::uint8_t> bytes;
  NavdataBuilder().build(in, bytes);
  std::size_t expected = 16 + 8;
  for (const auto& spec : navdata_option_specs()) expected += spec.size;
  CHECK(bytes.size() == expected);
  NavdataPacket out;
  const auto r = NavdataParser().parse(bytes, out);
  INFO(r.detail);
  REQUIRE(r.ok());
  for (const auto& spec : navdata_option_specs()) {
    INFO(spec.name);
    REQUIRE(out.has(spec.tag));
    CHECK(out.option(spec.tag).raw == in.option(spec.tag).raw);
  }
}

TEST_CASE("link: navdata refuses bad packets by kind", "[link]") {
  const auto good = handmade_demo_packet();
  NavdataParser parser;
  NavdataPacket p;
  auto expect = [&](std::vector<std::uint8_t> bytes, NavdataError error) {
    const auto r = parser.parse(bytes, p);
    INFO(r.detail);
    CHECK(r.error == error);
    if (!r.ok()) CHECK_FALSE(r.detail.empty());
  };
  expect({}, NavdataError::Truncated);
  expect(std::vector<std::uint8_t>(good.begin(), good.begin() + 20), NavdataError::Truncated);
  auto bad_magic = good;
  bad_magic[0] = 0x11;
  expect(bad_magic, NavdataError::BadMagic);
  auto bad_sum = good;
  bad_sum[30] ^= 0x01;
  expect(bad_sum, NavdataError::BadChecksum);
  auto bad_stored = good;
  bad_stored[bad_stored.size() - 2] ^= 0x80;
  expect(bad_stored, NavdataError::BadChecksum);
  auto overrun = good;
  overrun[18] = 0xFF;  // demo size = 0x??FF: runs past the datagram
  overrun[19] = 0x7F;
  expect(overrun, NavdataError::OptionOverrun);
  auto tiny = good;
  tiny[18] = 2;
  tiny[19] = 0;
  expect(tiny, NavdataError::OptionTooSmall);
  // A known option shorter than its layout (demo of 40 bytes), checksum recomputed.
  std::vector<std::uint8_t> short_demo(good.begin(), good.begin() + 16);
  put<std::uint16_t>(short_demo, 0);
  put<std::uint16_t>(short_demo, 40);
  short_demo.resize(short_demo.size() + 36, 0);
  put_checksum(short_demo);
  expect(short_demo, NavdataError::OptionTruncated);
  // No checksum at all.
  std::vector<std::uint8_t> no_cks(good.begin(), good.begin() + 16 + 148);
  expect(no_cks, NavdataError::NoChecksum);
  auto trailing = good;
  trailing.push_back(0);
  expect(trailing, NavdataError::DataAfterChecksum);
}

TEST_CASE("link: navdata sequence filter drops old packets and resets on com watchdog", "[link]") {
  NavdataSequenceFilter f;
  NavdataPacket p;
  p.sequence = 10;
  CHECK(f.accept(p));
  p.sequence = 9;
  CHECK_FALSE(f.accept(p));
  p.sequence = 10;
  CHECK_FALSE(f.accept(p));
  p.sequence = 11;
  CHECK(f.accept(p));
  p.sequence = 1;
  p.state = state_mask(kStateComWatchdog);
  CHECK(f.accept(p));
}
