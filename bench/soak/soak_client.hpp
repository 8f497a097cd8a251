#pragma once
// The soak's browser stand-in, on Boost.Beast over loopback: HTTP login (POST /api/login, the
// session cookie) and one WebSocket (/ws) per client, read all the time on a shared io_context as a
// page does, with what the scenario needs to know kept in a ClientView (control, the last ack, the
// mission's end, frames received). A slow reader's reading can be paused: it then reads nothing
// while the server's frames pile up in its socket buffers, which are made small for it.
#include <boost/asio/io_context.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

namespace labo::bench {

// HTTP on loopback: the status, or 0 when the server did not answer.
struct HttpAnswer {
  int status = 0;
  std::string body;
  std::string cookie;  // "labo_session=<token>" from Set-Cookie, when set
};
HttpAnswer http_request(unsigned short port, const std::string& method, const std::string& target,
                        const std::string& body = {}, const std::string& cookie = {});
// The session cookie, or empty when the login is refused.
std::string login(unsigned short port, const std::string& user, const std::string& password);

struct ClientView {
  bool open = false;
  bool controlling = false;
  std::uint64_t frames = 0;          // binary messages: JPEG frames or H.264 access units
  std::uint64_t messages = 0;        // JSON messages
  std::uint64_t acks_accepted = 0, acks_refused = 0;
  long last_ack_id = -1;  // the newest ack's command id, its verdict and reason
  bool last_ack_accepted = false;
  std::string last_ack_reason;
  std::uint64_t missions_ended = 0;  // "mission '...' ended: ..." events seen
  std::string last_ended;            // the last of them
  std::uint64_t safety_events = 0;   // "safety: ..." events (the safety monitor acted), and the last
  std::string last_safety;
  std::string mission = "idle";      // from telemetry
  std::string stage;
  bool flying = false;
};

class SoakClient : public std::enable_shared_from_this<SoakClient> {
 public:
  // Connects and upgrades (synchronously, from the caller's thread), then reads on `io`'s thread.
  // Throws boost::system::system_error when the server refuses. `small_buffer`: a 4 KiB receive
  // buffer, so a client that stops reading backs up into the server at once.
  static std::shared_ptr<SoakClient> connect(boost::asio::io_context& io, unsigned short port, const std::string& cookie,
                                             bool small_buffer = false);

  void send(const nlohmann::json& message);  // queued, written in order
  void pause_reading(bool paused);
  void close();
  ClientView view() const;

 private:
  explicit SoakClient(boost::asio::io_context& io);
  void read();
  void on_message(bool binary, std::string_view text);
  void write_next();

  boost::asio::io_context& io_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::deque<std::string> outbox_;  // io thread only
  bool paused_ = false;             // io thread only
  bool reading_ = false;            // io thread only
  mutable std::mutex mutex_;
  ClientView view_;
};

}  // namespace labo::bench
