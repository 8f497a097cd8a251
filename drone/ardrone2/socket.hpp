#pragma once
// Minimal RAII POSIX sockets for the AR.Drone link and its emulator: IPv4 UDP and TCP, every wait
// bounded by a timeout so that threads can notice a stop request.
#include <cstdint>
#include <netinet/in.h>
#include <span>
#include <string>

namespace labo::ardrone2 {

struct Endpoint {
  sockaddr_in addr{};
  static Endpoint resolve(const std::string& host, int port);  // throws std::runtime_error
  int port() const;
  bool operator==(const Endpoint& o) const;
};

class Socket {
 public:
  Socket() = default;
  explicit Socket(int fd) : fd_(fd) {}
  ~Socket();
  Socket(Socket&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  Socket& operator=(Socket&& o) noexcept;
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;

  static Socket udp(int bind_port = 0, const std::string& bind_host = "0.0.0.0");
  static Socket tcp_listen(int port, const std::string& bind_host = "127.0.0.1");
  // Connects with a timeout; an invalid Socket on failure.
  static Socket tcp_connect(const Endpoint& to, double timeout_s);

  bool valid() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  int local_port() const;
  // Waits at most timeout_s for readability.
  bool wait_readable(double timeout_s) const;
  // UDP: -1 on error or timeout (then 0 bytes).
  long receive_from(std::span<std::uint8_t> buffer, Endpoint& from, double timeout_s) const;
  bool send_to(std::span<const std::uint8_t> bytes, const Endpoint& to) const;
  // TCP: bytes read, 0 on timeout, -1 on EOF or error.
  long receive(std::span<std::uint8_t> buffer, double timeout_s) const;
  bool send_all(std::span<const std::uint8_t> bytes, double timeout_s) const;
  Socket accept(double timeout_s) const;
  void close();

 private:
  int fd_ = -1;
};

}  // namespace labo::ardrone2
