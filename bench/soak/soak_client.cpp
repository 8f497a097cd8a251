#include "bench/soak/soak_client.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http.hpp>
#include <chrono>

namespace labo::bench {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using asio::ip::tcp;

namespace {
const tcp::endpoint server_at(unsigned short port) { return {asio::ip::make_address("127.0.0.1"), port}; }
constexpr auto kHttpTimeout = std::chrono::seconds(15);
}  // namespace

HttpAnswer http_request(unsigned short port, const std::string& method, const std::string& target, const std::string& body,
                        const std::string& cookie) {
  // Asynchronous under a deadline on a private io_context: a server that hangs gives status 0, not a
  // soak that hangs.
  asio::io_context io;
  beast::tcp_stream stream(io);
  http::request<http::string_body> req{http::string_to_verb(method), target, 11};
  req.set(http::field::host, "127.0.0.1");
  if (!cookie.empty()) req.set(http::field::cookie, cookie);
  if (!body.empty()) {
    req.set(http::field::content_type, "application/json");
    req.body() = body;
  }
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  HttpAnswer answer;
  stream.expires_after(kHttpTimeout);
  stream.async_connect(server_at(port), [&](beast::error_code ec) {
    if (ec) return;
    http::async_write(stream, req, [&](beast::error_code ec, std::size_t) {
      if (ec) return;
      http::async_read(stream, buffer, res, [&](beast::error_code ec, std::size_t) {
        if (ec) return;
        answer.status = static_cast<int>(res.result_int());
        answer.body = res.body();
        const std::string set_cookie(res[http::field::set_cookie]);
        answer.cookie = set_cookie.substr(0, set_cookie.find(';'));
      });
    });
  });
  io.run();
  beast::error_code ignored;
  stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
  return answer;
}

std::string login(unsigned short port, const std::string& user, const std::string& password) {
  const HttpAnswer a =
      http_request(port, "POST", "/api/login", nlohmann::json{{"user", user}, {"password", password}}.dump());
  return a.status == 200 ? a.cookie : std::string();
}

SoakClient::SoakClient(asio::io_context& io) : io_(io), ws_(io) {}

std::shared_ptr<SoakClient> SoakClient::connect(asio::io_context& io, unsigned short port, const std::string& cookie,
                                                bool small_buffer) {
  std::shared_ptr<SoakClient> c(new SoakClient(io));
  auto& socket = beast::get_lowest_layer(c->ws_).socket();
  socket.open(tcp::v4());
  if (small_buffer) socket.set_option(asio::socket_base::receive_buffer_size(4096));
  socket.connect(server_at(port));
  // The close handshake gives up after this; reads have no idle limit (a slow reader is slow).
  websocket::stream_base::timeout timeouts{std::chrono::seconds(10), websocket::stream_base::none(), false};
  c->ws_.set_option(timeouts);
  c->ws_.set_option(websocket::stream_base::decorator(
      [cookie](websocket::request_type& req) { req.set(http::field::cookie, cookie); }));
  c->ws_.handshake("127.0.0.1", "/ws");
  c->view_.open = true;
  asio::post(io, [c] { c->read(); });
  return c;
}

void SoakClient::read() {
  if (paused_ || !ws_.is_open()) {
    reading_ = false;
    return;
  }
  reading_ = true;
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) {
      self->reading_ = false;
      std::lock_guard lock(self->mutex_);
      self->view_.open = false;
      self->view_.controlling = false;
      return;
    }
    const auto data = self->buffer_.cdata();
    self->on_message(!self->ws_.got_text(), std::string_view(static_cast<const char*>(data.data()), data.size()));
    self->buffer_.consume(self->buffer_.size());
    self->read();
  });
}

void SoakClient::on_message(bool binary, std::string_view text) {
  std::lock_guard lock(mutex_);
  if (binary) {
    ++view_.frames;
    return;
  }
  ++view_.messages;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) return;
  const std::string type = j.value("type", "");
  if (type == "control" && j.contains("you") && j["you"].is_object()) {
    view_.controlling = j["you"].value("controlling", false);
  } else if (type == "ack") {
    view_.last_ack_accepted = j.value("accepted", false);
    view_.last_ack_reason = j.value("reason", "");
    view_.last_ack_id = j.contains("id") && j["id"].is_number_integer() ? j["id"].get<long>() : -1;
    ++(view_.last_ack_accepted ? view_.acks_accepted : view_.acks_refused);
  } else if (type == "event") {
    const std::string message = j.value("message", "");
    if (message.find("' ended: ") != std::string::npos) {
      ++view_.missions_ended;
      view_.last_ended = message;
    }
    if (message.rfind("safety: ", 0) == 0) {
      ++view_.safety_events;
      view_.last_safety = message;
    }
  } else if (type == "telemetry") {
    view_.mission = j.value("mission", "idle");
    view_.stage = j.value("stage", "");
    view_.flying = j.value("flying", false);
  }
}

void SoakClient::send(const nlohmann::json& message) {
  asio::post(io_, [self = shared_from_this(), text = message.dump()] {
    self->outbox_.push_back(text);
    if (self->outbox_.size() == 1) self->write_next();
  });
}

void SoakClient::write_next() {
  if (outbox_.empty() || !ws_.is_open()) return;
  ws_.text(true);
  ws_.async_write(asio::buffer(outbox_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    self->outbox_.pop_front();
    if (ec) {
      self->outbox_.clear();
      return;
    }
    self->write_next();
  });
}

void SoakClient::pause_reading(bool paused) {
  asio::post(io_, [self = shared_from_this(), paused] {
    self->paused_ = paused;
    if (!paused && !self->reading_) self->read();
  });
}

void SoakClient::close() {
  asio::post(io_, [self = shared_from_this()] {
    if (!self->ws_.is_open()) return;
    if (self->paused_) {  // a slow reader leaves abruptly: a close handshake would wait behind its backlog
      beast::error_code ignored;
      beast::get_lowest_layer(self->ws_).socket().close(ignored);
      return;
    }
    self->ws_.async_close(websocket::close_code::normal, [self](beast::error_code) {
      beast::error_code ignored;
      beast::get_lowest_layer(self->ws_).socket().close(ignored);
    });
  });
}

ClientView SoakClient::view() const {
  std::lock_guard lock(mutex_);
  return view_;
}

}  // namespace labo::bench
