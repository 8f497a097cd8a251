#include "server/video/udp_sender.hpp"

#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <stdexcept>

namespace labo::server {

std::optional<UdpTarget> parse_udp_target(const std::string& text, std::string& error) {
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
    error = "'" + host + "' is not an IP address (expected an IPv4 or IPv6 literal: the media server is on a known address)";
    return std::nullopt;
  }
  const std::string port_text = text.substr(colon + 1);
  unsigned port = 0;
  const auto [end, err] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (err != std::errc{} || end != port_text.data() + port_text.size() || port == 0 || port > 65535) {
    error = "port '" + port_text + "': expected 1 to 65535";
    return std::nullopt;
  }
  return UdpTarget{host, static_cast<unsigned short>(port)};
}

UdpSender::UdpSender(const UdpTarget& target) : target_(target), socket_(io_) {
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(target.host, ec);
  if (ec) throw std::runtime_error("UDP target '" + target.host + "' is not an IP address");
  endpoint_ = {address, target.port};
  socket_.open(endpoint_.protocol());
  socket_.non_blocking(true);
}

bool UdpSender::send(std::span<const std::uint8_t> datagram) {
  boost::system::error_code ec;
  socket_.send_to(boost::asio::buffer(datagram.data(), datagram.size()), endpoint_, 0, ec);
  if (ec) {
    dropped_++;
    return false;
  }
  datagrams_++;
  bytes_ += datagram.size();
  return true;
}

bool UdpSender::send(std::span<const char> datagram) {
  return send(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()));
}

}  // namespace labo::server
