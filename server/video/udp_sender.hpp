#pragma once
// Datagrams to one UDP target on a known IP address (a media server's port), sent without ever
// blocking: a datagram the kernel cannot take at once, or one refused (nobody listening: ICMP port
// unreachable on loopback), is dropped and counted. For the RTP video and the geometry datagrams,
// whose callers are the drone link's threads. No allocation per datagram.
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace labo::server {

struct UdpTarget {
  std::string host = "127.0.0.1";
  unsigned short port = 0;
};

// "HOST:PORT" (an IPv4 or IPv6 literal, IPv6 in brackets) or nullopt; `error` says what was wrong.
std::optional<UdpTarget> parse_udp_target(const std::string& text, std::string& error);

struct UdpCounters {
  std::uint64_t datagrams = 0, bytes = 0, dropped = 0;
};

class UdpSender {
 public:
  // Throws std::runtime_error naming the target when its host is not an IP literal.
  explicit UdpSender(const UdpTarget& target);

  bool send(std::span<const std::uint8_t> datagram);  // false: dropped
  bool send(std::span<const char> datagram);
  UdpCounters counters() const { return {datagrams_.load(), bytes_.load(), dropped_.load()}; }
  const UdpTarget& target() const { return target_; }

 private:
  UdpTarget target_;
  boost::asio::io_context io_;  // the socket's; never run (sends are synchronous and non-blocking)
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint endpoint_;
  std::atomic<std::uint64_t> datagrams_{0}, bytes_{0}, dropped_{0};
};

}  // namespace labo::server
