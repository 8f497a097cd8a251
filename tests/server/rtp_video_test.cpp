#include <boost/asio/ip/udp.hpp>
#include <catch2/catch.hpp>
#include <cstdint>
#include <map>
#include <vector>

#include "server/serve_command.hpp"
#include "server/video/access_unit_wire.hpp"
#include "server/video/rtp_video_tap.hpp"
#include "tests/server/support/server_fixture.hpp"
#include "tests/server/support/test_clients.hpp"

using namespace labo;
using namespace labo::server;
using namespace labo::server::test;
using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

namespace {

// One NAL unit: its header byte, then `size - 1` body bytes that never form a start code.
Bytes nal(std::uint8_t header, std::size_t size) {
  Bytes n(size);
  n[0] = header;
  for (std::size_t i = 1; i < size; ++i) n[i] = static_cast<std::uint8_t>(1 + i % 251);
  return n;
}

Bytes annexb(const std::vector<Bytes>& nals, bool four_byte_codes = true) {
  Bytes out;
  for (const Bytes& n : nals) {
    if (four_byte_codes) out.push_back(0);
    out.insert(out.end(), {0, 0, 1});
    out.insert(out.end(), n.begin(), n.end());
  }
  return out;
}

struct RtpPacket {
  bool marker = false;
  std::uint8_t payload_type = 0;
  std::uint16_t sequence = 0;
  std::uint32_t timestamp = 0, ssrc = 0;
  Bytes payload;
};

RtpPacket parse_rtp(std::span<const std::uint8_t> p) {
  REQUIRE(p.size() > 12);
  REQUIRE(p[0] == 0x80);
  RtpPacket r;
  r.marker = (p[1] & 0x80) != 0;
  r.payload_type = p[1] & 0x7f;
  r.sequence = static_cast<std::uint16_t>(p[2] << 8 | p[3]);
  for (int i = 0; i < 4; ++i) {
    r.timestamp = r.timestamp << 8 | p[4 + i];
    r.ssrc = r.ssrc << 8 | p[8 + i];
  }
  r.payload.assign(p.begin() + 12, p.end());
  return r;
}

// The NAL units back from RFC 6184 payloads (single NAL unit packets and FU-A), as a receiver would.
std::vector<Bytes> depacketize(const std::vector<RtpPacket>& packets) {
  std::vector<Bytes> nals;
  for (const RtpPacket& p : packets) {
    const std::uint8_t type = p.payload[0] & 0x1f;
    if (type != 28) {
      nals.push_back(p.payload);
      continue;
    }
    const std::uint8_t fu = p.payload[1];
    if (fu & 0x80) nals.push_back({static_cast<std::uint8_t>((p.payload[0] & 0xe0) | (fu & 0x1f))});
    REQUIRE(!nals.empty());
    nals.back().insert(nals.back().end(), p.payload.begin() + 2, p.payload.end());
  }
  return nals;
}

std::vector<RtpPacket> packetize(RtpH264Packetizer& packetizer, const Bytes& unit, std::uint32_t timestamp) {
  std::vector<RtpPacket> out;
  packetizer.packetize(unit, timestamp, [&](std::span<const std::uint8_t> p) { out.push_back(parse_rtp(p)); });
  return out;
}

// A flight that only keeps the sink it is given: the test plays the runtime's link thread.
class SinkOnlyFlight final : public FlightService {
 public:
  void set_sink(FlightEventSink* sink) override { sink_ = sink; }
  CommandVerdict request(const MissionCommand&) override { return {}; }
  FlightTelemetry telemetry() const override { return {}; }
  std::vector<InstrumentSummary> instruments() const override { return {}; }
  void land_and_stop(double) override {}
  FlightEventSink* sink_ = nullptr;
};

}  // namespace

TEST_CASE("web: RTP: small NAL units go whole, large ones as FU-A fragments, the marker on the unit's last packet") {
  RtpH264Packetizer packetizer({.max_packet_bytes = 100, .payload_type = 96, .ssrc = 7});
  const Bytes sps = nal(0x67, 10), pps = nal(0x68, 4), idr = nal(0x65, 300);
  const std::vector<RtpPacket> packets = packetize(packetizer, annexb({sps, pps, idr}), 1234);

  // 88 payload bytes per packet: SPS, PPS whole; the IDR's 299 body bytes in ceil(299 / 86) = 4 FU-As.
  REQUIRE(packets.size() == 6);
  for (std::size_t i = 0; i < packets.size(); ++i) {
    CHECK(packets[i].sequence == i);
    CHECK(packets[i].timestamp == 1234);
    CHECK(packets[i].payload_type == 96);
    CHECK(packets[i].ssrc == 7);
    CHECK(packets[i].marker == (i + 1 == packets.size()));
    CHECK(packets[i].payload.size() + 12 <= 100);
  }
  CHECK(packets[2].payload[0] == (0x60 | 28));  // FU indicator: the IDR's NRI, type FU-A
  CHECK(packets[2].payload[1] == (0x80 | 5));   // start bit, type IDR
  CHECK(packets[3].payload[1] == 5);
  CHECK(packets[5].payload[1] == (0x40 | 5));   // end bit
  CHECK(depacketize(packets) == std::vector<Bytes>{sps, pps, idr});
  CHECK(packetizer.next_sequence() == 6);
}

TEST_CASE("web: RTP: 3- and 4-byte start codes, delimiters and filler dropped, trailing zeros trimmed") {
  RtpH264Packetizer packetizer;
  const Bytes aud = nal(0x09, 2), slice = nal(0x41, 50), filler = nal(0x0c, 20);
  Bytes unit = annexb({aud, slice, filler}, false);
  unit.insert(unit.end(), {0, 0});  // trailing_zero_8bits after the last NAL unit
  Bytes with_zeros = annexb({slice}, true);
  with_zeros.insert(with_zeros.end(), {0, 0, 0});
  const auto packets = packetize(packetizer, unit, 1);
  REQUIRE(packets.size() == 1);
  CHECK(packets[0].marker);  // the slice is the last NAL unit sent: the filler after it is not
  CHECK(packets[0].payload == slice);
  CHECK(depacketize(packetize(packetizer, with_zeros, 2)) == std::vector<Bytes>{slice});
  CHECK(packetize(packetizer, {}, 3).empty());
  CHECK(packetize(packetizer, {0, 0, 1}, 3).empty());
  CHECK(packetize(packetizer, nal(0x41, 30), 3).empty());  // no start code: not Annex-B
}

TEST_CASE("web: RTP: the timestamp is the capture time at 90 kHz, modulo 2^32") {
  CHECK(rtp_timestamp_of(0) == 0);
  CHECK(rtp_timestamp_of(1000.0) == 90000);
  CHECK(rtp_timestamp_of(1000.0 / 30) == 3000);
  // A capture time of today: 1.7e12 ms * 90 wraps; the page computes it with the same rounding.
  const double t = 1764838800123.4;
  CHECK(rtp_timestamp_of(t) == static_cast<std::uint32_t>(static_cast<std::uint64_t>(std::llround(t * 90)) % 4294967296ull));
  CHECK(rtp_timestamp_of(t + 1000.0 / 30) - rtp_timestamp_of(t) == 3000);
}

TEST_CASE("web: RTP: refused packetizer options and forwarding targets name what was expected") {
  CHECK_THROWS_WITH(RtpH264Packetizer({.max_packet_bytes = 14}), Catch::Contains("expected 15 to 65507"));
  CHECK_THROWS_WITH(RtpH264Packetizer({.payload_type = 200}), Catch::Contains("expected 0 to 127"));
  std::string error;
  CHECK(parse_udp_target("127.0.0.1:20000", error)->port == 20000);
  CHECK(parse_udp_target("[::1]:5004", error)->host == "::1");
  CHECK_FALSE(parse_udp_target("127.0.0.1", error));
  CHECK(error.find("expected HOST:PORT") != std::string::npos);
  CHECK_FALSE(parse_udp_target("janus.local:5004", error));
  CHECK(error.find("not an IP address") != std::string::npos);
  CHECK_FALSE(parse_udp_target("127.0.0.1:0", error));
  CHECK_FALSE(parse_udp_target("127.0.0.1:70000", error));
  CHECK_FALSE(parse_udp_target("127.0.0.1:50x", error));
  CHECK(error.find("expected 1 to 65535") != std::string::npos);
}

TEST_CASE("web: RTP: serve refuses --geometry-udp without --rtp-video, and a target that is no IP:PORT, naming the option") {
  const auto refusal = [](const std::vector<std::string>& argv) {
    try {
      run_serve_command(parse_args(serve_command_spec(), argv));
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(refusal({"--geometry-udp", "127.0.0.1:20001"}) ==
        "--geometry-udp needs --rtp-video: the geometry goes with the video it overlays");
  CHECK_THAT(refusal({"--rtp-video", "janus.local:20000"}), Catch::StartsWith("--rtp-video ") && Catch::Contains("not an IP address"));
  CHECK_THAT(refusal({"--rtp-video", "127.0.0.1:20000", "--geometry-udp", "127.0.0.1"}),
             Catch::StartsWith("--geometry-udp ") && Catch::Contains("expected HOST:PORT"));
}

TEST_CASE("web: RTP: the tap forwards every access unit of the drone's stream over UDP, whether or not a WebSocket viewer wants it") {
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket receiver(io, {asio::ip::make_address("127.0.0.1"), 0});
  RtpVideoForwarder forwarder({"127.0.0.1", receiver.local_endpoint().port()});
  SinkOnlyFlight flight;
  RtpVideoTap tap(flight, forwarder);  // no outer sink: nobody on the WebSocket
  REQUIRE(flight.sink_);
  CHECK(flight.sink_->wants_access_units());
  CHECK_FALSE(flight.sink_->wants_jpeg());

  const Bytes unit = annexb({nal(0x67, 10), nal(0x68, 4), nal(0x65, 3000)});
  AccessUnitPacker packer;
  WireAccessUnit wire = packer.pack({0, CameraId::Front, 42, true, 640, 360, unit}, 1764838800000.0);
  flight.sink_->on_access_unit(wire);

  std::vector<RtpPacket> packets;
  Bytes datagram(2048);
  while (packets.empty() || !packets.back().marker) {
    const std::size_t n = receiver.receive(asio::buffer(datagram));
    packets.push_back(parse_rtp({datagram.data(), n}));
  }
  CHECK(packets.front().timestamp == rtp_timestamp_of(1764838800000.0));
  CHECK(depacketize(packets) == std::vector<Bytes>{nal(0x67, 10), nal(0x68, 4), nal(0x65, 3000)});
  const RtpForwarderCounters c = forwarder.counters();
  CHECK(c.units == 1);
  CHECK(c.packets == packets.size());
  CHECK(c.packets_dropped == 0);

  // The shared low rendition is the WebSocket's slow viewers' own: the media server gets the drone's stream only.
  flight.sink_->on_access_unit(packer.pack({0, CameraId::Front, 43, true, 640, 360, unit}, 1764838800033.0, Rendition::Low));
  CHECK(forwarder.counters().units == 1);
}

TEST_CASE("web: RTP: with a geometry forwarder the tap sends each unit's geometry to the data port, the low rendition's not") {
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket video(io, {asio::ip::make_address("127.0.0.1"), 0});
  asio::ip::udp::socket data(io, {asio::ip::make_address("127.0.0.1"), 0});
  RtpVideoForwarder forwarder({"127.0.0.1", video.local_endpoint().port()});
  GeometryForwarder geometry({"127.0.0.1", data.local_endpoint().port()});
  SinkOnlyFlight flight;
  RtpVideoTap tap(flight, forwarder, &geometry);
  REQUIRE(flight.sink_);

  AccessUnitPacker packer;
  const Bytes unit = annexb({nal(0x67, 10), nal(0x68, 4), nal(0x65, 300)});
  WireAccessUnit source = packer.pack({0, CameraId::Front, 42, true, 640, 360, unit}, 1764838800000.0);
  source.geometry = std::make_shared<const std::string>(R"({"type":"overlay","frame":42})");
  WireAccessUnit low = packer.pack({0, CameraId::Front, 42, true, 640, 360, unit}, 1764838800000.0, Rendition::Low);
  low.geometry = source.geometry;
  flight.sink_->on_access_unit(source);
  flight.sink_->on_access_unit(low);

  std::vector<char> datagram(2048);
  const std::size_t n = data.receive(asio::buffer(datagram));
  CHECK(std::string(datagram.data(), n) == "LDG1 42 0 1\n" + *source.geometry);
  CHECK(geometry.counters().frames == 1);
  CHECK(forwarder.counters().units == 1);
}

TEST_CASE("web: a geometry viewer gets each access unit's overlay as JSON and no video") {
  ServerFixture f;
  WsClient viewer(f.port, login_cookie(f.port, "alice", "alice-pw"));
  viewer.send(json{{"type", "subscribe"}, {"video", "geometry"}});
  const auto subscribed = viewer.wait_for("subscribed");
  REQUIRE(subscribed);
  CHECK((*subscribed)["video"] == "geometry");
  f.flight.publish_frame(6);  // JPEG: not for this viewer
  f.flight.publish_access_unit(7, true);
  f.flight.publish_access_unit(8, false);
  std::vector<int> overlays;
  int binary = 0;
  while (overlays.size() < 2) {
    const auto m = viewer.read(3.0);
    REQUIRE(m);
    if (m->binary) {
      ++binary;
      continue;
    }
    const json j = m->json();
    if (j.value("type", "") == "overlay") overlays.push_back(j["frame"].get<int>());
  }
  CHECK(overlays == std::vector<int>{7, 8});
  CHECK(binary == 0);
}

TEST_CASE("web: a viewer on the none path (video and overlays from the media server) gets telemetry and no video or overlay") {
  ServerFixture f;
  WsClient viewer(f.port, login_cookie(f.port, "alice", "alice-pw"));
  viewer.send(json{{"type", "subscribe"}, {"video", "none"}});
  const auto subscribed = viewer.wait_for("subscribed");
  REQUIRE(subscribed);
  CHECK((*subscribed)["video"] == "none");
  f.flight.publish_frame(6);
  f.flight.publish_access_unit(7, true);
  f.flight.publish_access_unit(8, false);
  int binary = 0, overlays = 0, telemetry = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(1500);
  while (std::chrono::steady_clock::now() < end) {
    const auto m = viewer.read(0.5);
    if (!m) continue;
    if (m->binary) ++binary;
    else if (const std::string type = m->json().value("type", ""); type == "overlay") ++overlays;
    else telemetry += type == "telemetry";
  }
  CHECK(binary == 0);
  CHECK(overlays == 0);
  CHECK(telemetry > 0);
}

TEST_CASE("web: RTP: the tap passes the lab's changes through to the flight software: instruments and the set-down") {
  // Behind the tap (serve with --rtp-video) an admin still places and removes instruments and sets
  // the drone down: the tap answered them with the base class's refusal before.
  RtpVideoForwarder forwarder({"127.0.0.1", 9});
  ScriptedFlight flight;
  RtpVideoTap tap(flight, forwarder);
  lab::InstrumentSpec spec;
  spec.id = "multimeter";
  CHECK(tap.add_instrument(spec).accepted);
  CHECK(flight.placed.size() == 1);
  CHECK(tap.remove_instrument("multimeter").accepted);
  CHECK(tap.set_down_on_platform().accepted);
  CHECK(flight.set_downs == 1);
  CHECK(tap.lab_outline().known);
  CHECK(tap.lab_outline().benches.size() == flight.lab_outline().benches.size());
}
