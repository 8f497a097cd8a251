#pragma once
// Loopback clients for the server tests, on Beast's own HTTP and WebSocket client. Tests only.
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace labo::server::test {

namespace beast = boost::beast;
namespace http = beast::http;
namespace asio = boost::asio;

struct HttpResult {
  int status = 0;
  std::string body;
  std::string set_cookie;
  std::string content_type;
  nlohmann::json json() const { return nlohmann::json::parse(body, nullptr, false); }
};

inline HttpResult http_call(unsigned short port, http::verb method, const std::string& target, const std::string& body = {},
                            const std::string& cookie = {}, const std::string& content_type = "application/json") {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, "127.0.0.1");
  if (!cookie.empty()) req.set(http::field::cookie, cookie);
  if (!body.empty()) {
    req.set(http::field::content_type, content_type);
    req.body() = body;
  }
  req.prepare_payload();
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  beast::error_code ec;
  stream.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ec);
  return {static_cast<int>(res.result_int()), res.body(), std::string(res[http::field::set_cookie]),
          std::string(res[http::field::content_type])};
}

// Sends raw bytes and returns the status line's code (0 when the server closed without answering).
inline int raw_status(unsigned short port, const std::string& bytes) {
  asio::io_context io;
  asio::ip::tcp::socket s(io);
  s.connect({asio::ip::make_address("127.0.0.1"), port});
  asio::write(s, asio::buffer(bytes));
  std::string reply(256, '\0');
  beast::error_code ec;
  const std::size_t n = s.read_some(asio::buffer(reply), ec);
  return n < 12 ? 0 : std::stoi(reply.substr(9, 3));
}

// "labo_session=<token>" for the Cookie header.
inline std::string login_cookie(unsigned short port, const std::string& user, const std::string& password) {
  const HttpResult r = http_call(port, http::verb::post, "/api/login",
                                 nlohmann::json{{"user", user}, {"password", password}}.dump());
  if (r.status != 200) return {};
  return r.set_cookie.substr(0, r.set_cookie.find(';'));
}

class WsClient {
 public:
  // `origin`: the Origin header a browser would send (none by default, as scripts send).
  // `receive_buffer` > 0: the socket's receive buffer, set before connecting (a small one makes a
  // client that reads slowly look like a slow link to the server: the bytes wait on its side).
  WsClient(unsigned short port, const std::string& cookie, const std::string& origin = {}, int receive_buffer = 0) : ws_(io_) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    socket.open(asio::ip::tcp::v4());
    if (receive_buffer > 0) socket.set_option(asio::socket_base::receive_buffer_size(receive_buffer));
    beast::get_lowest_layer(ws_).connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    ws_.set_option(beast::websocket::stream_base::decorator([cookie, origin](beast::websocket::request_type& req) {
      req.set(http::field::cookie, cookie);
      if (!origin.empty()) req.set(http::field::origin, origin);
    }));
    ws_.handshake("127.0.0.1:" + std::to_string(port), "/ws");  // as a browser names the host
  }

  void send(const std::string& text) {
    ws_.text(true);
    ws_.write(asio::buffer(text));
  }
  void send(const nlohmann::json& j) { send(j.dump()); }

  struct Message {
    bool binary = false;
    std::string data;
    nlohmann::json json() const { return nlohmann::json::parse(data, nullptr, false); }
  };

  // The next message, or nullopt after timeout_s (the client is unusable after a timeout).
  std::optional<Message> read(double timeout_s = 3.0) {
    buffer_.clear();
    bool done = false;
    beast::error_code result;
    ws_.async_read(buffer_, [&](beast::error_code ec, std::size_t) {
      done = true;
      result = ec;
    });
    io_.restart();
    io_.run_for(std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::duration<double>(timeout_s)));
    if (!done || result) return std::nullopt;
    return Message{!ws_.got_text(), beast::buffers_to_string(buffer_.data())};
  }

  // Reads until a JSON message whose "type" is `type` (and that `match` accepts) arrives.
  template <typename Match>
  std::optional<nlohmann::json> wait_for(const std::string& type, Match match, double timeout_s = 5.0) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
      auto m = read(left);
      if (!m) return std::nullopt;
      if (m->binary) continue;
      auto j = m->json();
      if (j.value("type", "") == type && match(j)) return j;
    }
    return std::nullopt;
  }
  std::optional<nlohmann::json> wait_for(const std::string& type, double timeout_s = 5.0) {
    return wait_for(type, [](const nlohmann::json&) { return true; }, timeout_s);
  }
  std::optional<Message> wait_for_frame(double timeout_s = 5.0) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      auto m = read(std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
      if (!m) return std::nullopt;
      if (m->binary) return m;
    }
    return std::nullopt;
  }

 private:
  asio::io_context io_;
  beast::websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
};

// A viewer that stops reading: a WebSocket handshake (and optionally one text message, e.g. a
// subscription), then never a read. Its tiny receive buffer fills at once.
class StuckViewer {
 public:
  StuckViewer(unsigned short port, const std::string& cookie, const std::string& first_message = {}) : ws_(io_) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    socket.open(asio::ip::tcp::v4());
    socket.set_option(asio::socket_base::receive_buffer_size(4096));
    beast::get_lowest_layer(ws_).connect({asio::ip::make_address("127.0.0.1"), port});
    ws_.set_option(beast::websocket::stream_base::decorator(
        [cookie](beast::websocket::request_type& r) { r.set(http::field::cookie, cookie); }));
    ws_.handshake("127.0.0.1", "/ws");
    if (first_message.empty()) return;
    ws_.text(true);
    ws_.write(asio::buffer(first_message));
  }

 private:
  asio::io_context io_;
  beast::websocket::stream<beast::tcp_stream> ws_;
};

}  // namespace labo::server::test
