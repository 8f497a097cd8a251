#include <boost/asio/ip/udp.hpp>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "server/video/geometry_datagrams.hpp"
#include "server/video/geometry_forwarder.hpp"

using namespace labo;
using namespace labo::server;

namespace {

struct Part {
  std::string header, body;
};

std::vector<Part> split(GeometryDatagrams& d, std::uint32_t frame, const std::string& geometry) {
  std::vector<Part> parts;
  d.split(frame, geometry, [&](std::span<const char> datagram) {
    REQUIRE(datagram.size() <= GeometryDatagrams::kMaxDatagram);
    const std::string text(datagram.data(), datagram.size());
    const std::size_t newline = text.find('\n');
    REQUIRE(newline != std::string::npos);
    parts.push_back({text.substr(0, newline), text.substr(newline + 1)});
  });
  return parts;
}

bool ends_inside_utf8_sequence(const std::string& s) {
  // The last lead byte's sequence length against the bytes after it.
  for (std::size_t back = 0; back < 4 && back < s.size(); ++back) {
    const auto c = static_cast<unsigned char>(s[s.size() - 1 - back]);
    if ((c & 0xC0) == 0x80) continue;  // a continuation byte: keep looking for the lead
    const std::size_t length = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : 4;
    return back + 1 < length;
  }
  return false;
}

}  // namespace

TEST_CASE("web: geometry datagrams: a small overlay goes whole, with its frame number") {
  GeometryDatagrams d;
  const std::string overlay = R"({"type":"overlay","frame":7,"capture_ms":1764838800000})";
  const auto parts = split(d, 7, overlay);
  REQUIRE(parts.size() == 1);
  CHECK(parts[0].header == "LDG1 7 0 1");
  CHECK(parts[0].body == overlay);
  CHECK(d.split(8, "", [](std::span<const char>) { FAIL("an empty geometry sends nothing"); }) == 0);
}

TEST_CASE("web: geometry datagrams: a large overlay goes in parts within the MTU, never splitting a UTF-8 character") {
  GeometryDatagrams d;
  // ASCII with two-, three- and four-byte characters spread over several parts.
  std::string overlay = R"({"type":"overlay","mission":")";
  for (int i = 0; i < 900; ++i) overlay += i % 3 == 0 ? "é" : i % 3 == 1 ? "€" : "a\xF0\x9F\x9A\x81";
  overlay += R"("})";
  const auto parts = split(d, 4294967295u, overlay);
  REQUIRE(parts.size() >= 3);
  std::string joined;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    CHECK(parts[i].header == "LDG1 4294967295 " + std::to_string(i) + " " + std::to_string(parts.size()));
    CHECK_FALSE(ends_inside_utf8_sequence(parts[i].body));
    joined += parts[i].body;
  }
  CHECK(joined == overlay);
}

TEST_CASE("web: geometry datagrams reach the media server's data port, counted") {
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket receiver(io, {asio::ip::make_address("127.0.0.1"), 0});
  GeometryForwarder forwarder({"127.0.0.1", receiver.local_endpoint().port()});
  const std::string overlay(3000, 'x');
  forwarder.forward(12, overlay);
  std::string joined;
  std::vector<char> datagram(2048);
  for (int i = 0; i < 3; ++i) {
    const std::size_t n = receiver.receive(asio::buffer(datagram));
    const std::string text(datagram.data(), n);
    CHECK(text.rfind("LDG1 12 " + std::to_string(i) + " 3\n", 0) == 0);
    joined += text.substr(text.find('\n') + 1);
  }
  CHECK(joined == overlay);
  const GeometryForwarderCounters c = forwarder.counters();
  CHECK(c.frames == 1);
  CHECK(c.datagrams == 3);
  CHECK(c.dropped == 0);
}
