#include "server/video/rtp_video_forwarder.hpp"

#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <stdexcept>

#include "server/video/access_unit_wire.hpp"

namespace labo {

std::optional<RtpTarget> parse_rtp_target(const std::string& text, std::string& error) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    error = "'" + text + "': expected HOST:PORT, e.g. 127.0.0.1:20000";
    return std::nullopt;
  }
  std::string host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  boost::system::error_code ec;
  boost::asio::ip::make_address(host, ec);
  if (ec) {
    error = "'" + host + "' is not an IP address (expected an IPv4 or IPv6 literal: RTP goes to a media server on a known address)";
    return std::nullopt;
  }
  const std::string port_text = text.substr(colon + 1);
  unsigned port = 0;
  const auto [end, err] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (err != std::errc{} || end != port_text.data() + port_text.size() || port == 0 || port > 65535) {
    error = "port '" + port_text + "': expected 1 to 65535";
    return std::nullopt;
  }
  return RtpTarget{host, static_cast<unsigned short>(port)};
}

RtpVideoForwarder::RtpVideoForwarder(const RtpTarget& target, RtpPacketizerOptions options)
    : target_(target), socket_(io_), packetizer_(options) {
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(target.host, ec);
  if (ec) throw std::runtime_error("RTP target '" + target.host + "' is not an IP address");
  endpoint_ = {address, target.port};
  socket_.open(endpoint_.protocol());
  socket_.non_blocking(true);
}

void RtpVideoForwarder::forward(const WireAccessUnit& unit) {
  if (!unit.wire || unit.wire->size() < AccessUnitHeader::kSize) return;
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(unit.wire->data());
  const std::span<const std::uint8_t> annexb(bytes + AccessUnitHeader::kSize, unit.wire->size() - AccessUnitHeader::kSize);
  units_++;
  packetizer_.packetize(annexb, rtp_timestamp_of(unit.capture_unix_ms), [this](std::span<const std::uint8_t> packet) {
    boost::system::error_code ec;
    socket_.send_to(boost::asio::buffer(packet.data(), packet.size()), endpoint_, 0, ec);
    if (ec) {  // would block, or nobody listening (ICMP port unreachable on loopback): dropped
      dropped_++;
      return;
    }
    packets_++;
    bytes_ += packet.size();
  });
}

RtpForwarderCounters RtpVideoForwarder::counters() const { return {units_.load(), packets_.load(), bytes_.load(), dropped_.load()}; }

}  // namespace labo
