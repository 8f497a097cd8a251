#include "drone/ardrone2/socket.hpp"

#include <arpa/inet.h>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdexcept>
#include <sys/socket.h>
#include <unistd.h>

namespace labo::ardrone2 {

namespace {
int to_ms(double s) { return s <= 0 ? 0 : static_cast<int>(s * 1000.0 + 0.5); }

bool wait_for(int fd, short events, double timeout_s) {
  pollfd p{fd, events, 0};
  for (;;) {
    const int rc = ::poll(&p, 1, to_ms(timeout_s));
    if (rc < 0 && errno == EINTR) continue;
    return rc > 0;
  }
}
}  // namespace

Endpoint Endpoint::resolve(const std::string& host, int port) {
  if (port < 0 || port > 65535) throw std::runtime_error("port " + std::to_string(port) + " outside 0..65535");
  Endpoint e;
  e.addr.sin_family = AF_INET;
  e.addr.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::inet_pton(AF_INET, host.c_str(), &e.addr.sin_addr) == 1) return e;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* res = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &res) != 0 || !res)
    throw std::runtime_error("cannot resolve host '" + host + "'");
  e.addr.sin_addr = reinterpret_cast<sockaddr_in*>(res->ai_addr)->sin_addr;
  ::freeaddrinfo(res);
  return e;
}

int Endpoint::port() const { return ntohs(addr.sin_port); }
bool Endpoint::operator==(const Endpoint& o) const {
  return addr.sin_addr.s_addr == o.addr.sin_addr.s_addr && addr.sin_port == o.addr.sin_port;
}

Socket::~Socket() { close(); }

Socket& Socket::operator=(Socket&& o) noexcept {
  if (this != &o) {
    close();
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

void Socket::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Socket Socket::udp(int bind_port, const std::string& bind_host) {
  Socket s(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!s.valid()) throw std::runtime_error(std::string("udp socket: ") + std::strerror(errno));
  const Endpoint e = Endpoint::resolve(bind_host, bind_port);
  if (::bind(s.fd_, reinterpret_cast<const sockaddr*>(&e.addr), sizeof(e.addr)) != 0)
    throw std::runtime_error("cannot bind UDP port " + std::to_string(bind_port) + ": " + std::strerror(errno));
  return s;
}

Socket Socket::tcp_listen(int port, const std::string& bind_host) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!s.valid()) throw std::runtime_error(std::string("tcp socket: ") + std::strerror(errno));
  const int one = 1;
  ::setsockopt(s.fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  const Endpoint e = Endpoint::resolve(bind_host, port);
  if (::bind(s.fd_, reinterpret_cast<const sockaddr*>(&e.addr), sizeof(e.addr)) != 0 || ::listen(s.fd_, 4) != 0)
    throw std::runtime_error("cannot listen on TCP port " + std::to_string(port) + ": " + std::strerror(errno));
  return s;
}

Socket Socket::tcp_connect(const Endpoint& to, double timeout_s) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
  if (!s.valid()) return s;
  const int rc = ::connect(s.fd_, reinterpret_cast<const sockaddr*>(&to.addr), sizeof(to.addr));
  if (rc != 0) {
    if (errno != EINPROGRESS || !wait_for(s.fd_, POLLOUT, timeout_s)) return Socket();
    int err = 0;
    socklen_t len = sizeof(err);
    if (::getsockopt(s.fd_, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) return Socket();
  }
  const int one = 1;
  ::setsockopt(s.fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return s;
}

int Socket::local_port() const {
  sockaddr_in a{};
  socklen_t len = sizeof(a);
  if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0) return -1;
  return ntohs(a.sin_port);
}

bool Socket::wait_readable(double timeout_s) const { return wait_for(fd_, POLLIN, timeout_s); }

long Socket::receive_from(std::span<std::uint8_t> buffer, Endpoint& from, double timeout_s) const {
  if (!wait_readable(timeout_s)) return -1;
  socklen_t len = sizeof(from.addr);
  const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT | MSG_TRUNC,
                               reinterpret_cast<sockaddr*>(&from.addr), &len);
  return n < 0 ? -1 : static_cast<long>(n);
}

bool Socket::send_to(std::span<const std::uint8_t> bytes, const Endpoint& to) const {
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL,
                             reinterpret_cast<const sockaddr*>(&to.addr), sizeof(to.addr));
  return n == static_cast<ssize_t>(bytes.size());
}

long Socket::receive(std::span<std::uint8_t> buffer, double timeout_s) const {
  if (!wait_readable(timeout_s)) return 0;
  const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return 0;
  return n <= 0 ? -1 : static_cast<long>(n);
}

bool Socket::send_all(std::span<const std::uint8_t> bytes, double timeout_s) const {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    if (!wait_for(fd_, POLLOUT, timeout_s)) return false;
    const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

Socket Socket::accept(double timeout_s) const {
  if (!wait_readable(timeout_s)) return Socket();
  Socket s(::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK));
  if (s.valid()) {
    const int one = 1;
    ::setsockopt(s.fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  }
  return s;
}

}  // namespace labo::ardrone2
