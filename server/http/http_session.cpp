#include "server/http/http_session.hpp"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <optional>

#include "server/http/origin_check.hpp"
#include "server/http/server_context.hpp"
#include "server/http/websocket_session.hpp"

namespace labo::server {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// `Stream` is plain TCP (beast::tcp_stream) or TLS over it (TlsStream): the same session either way.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

 public:
  HttpSession(Stream&& stream, std::shared_ptr<ServerContext> ctx) : stream_(std::move(stream)), ctx_(std::move(ctx)) {
    beast::error_code ec;
    const auto ep = beast::get_lowest_layer(stream_).socket().remote_endpoint(ec);
    remote_ = ec ? "unknown" : ep.address().to_string();
  }

  void run() {
    if constexpr (kTls) {
      asio::dispatch(stream_.get_executor(), [self = this->shared_from_this()] {
        beast::get_lowest_layer(self->stream_).expires_after(std::chrono::seconds(30));
        self->stream_.async_handshake(asio::ssl::stream_base::server, [self](beast::error_code ec) {
          if (ec) return self->close();  // not TLS, or a client that does not trust the certificate
          self->do_read();
        });
      });
    } else {
      asio::dispatch(stream_.get_executor(), beast::bind_front_handler(&HttpSession::do_read, this->shared_from_this()));
    }
  }

 private:
  std::shared_ptr<HttpSession> self() { return this->shared_from_this(); }

  void do_read() {
    parser_.emplace();
    parser_->header_limit(16 * 1024);
    parser_->body_limit(ctx_->settings.clients.max_body_bytes);
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
    http::async_read_header(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::on_header, self()));
  }

  void on_header(beast::error_code ec, std::size_t) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == asio::error::operation_aborted) return close();
    if (ec == http::error::body_limit) return reply_and_close(too_large());
    if (ec == http::error::header_limit) return reply_and_close(HttpReply::error(http::status::request_header_fields_too_large, "request header over 16 KiB"));
    if (ec) return reply_and_close(HttpReply::error(http::status::bad_request, "malformed HTTP request: " + ec.message()));
    const auto& req = parser_->get();
    // Boost 1.74 does not check Content-Length against body_limit (fixed in Beast v313): do it here,
    // before a byte of the body is read.
    if (const auto length = parser_->content_length(); length && *length > ctx_->settings.clients.max_body_bytes)
      return reply_and_close(too_large());
    if (beast::websocket::is_upgrade(req)) return upgrade();
    if (parser_->is_done()) return on_body({}, 0);
    http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::on_body, self()));
  }

  void on_body(beast::error_code ec, std::size_t) {
    if (ec == http::error::body_limit) return reply_and_close(too_large());
    if (ec == http::error::end_of_stream || ec == beast::error::timeout) return close();
    if (ec) return reply_and_close(HttpReply::error(http::status::bad_request, "malformed HTTP body: " + ec.message()));
    const HttpRequest req = parser_->release();
    HttpReply reply = ctx_->api.handle(req, remote_);
    const bool head = req.method() == http::verb::head;
    if (reply.deferred) return answer_later(std::move(reply.deferred), req.keep_alive(), req.version(), head);
    send(std::move(reply), req.keep_alive(), req.version(), head);
  }

  // The reply comes from another thread: it is sent on this connection's strand, with a fresh
  // timeout (the read's has run on while the work was done). Nothing is read meanwhile.
  void answer_later(std::function<void(std::function<void(HttpReply)>)> work, bool keep_alive, unsigned version, bool head) {
    work([self = self(), keep_alive, version, head](HttpReply reply) {
      asio::post(self->stream_.get_executor(), [self, reply = std::move(reply), keep_alive, version, head]() mutable {
        beast::get_lowest_layer(self->stream_).expires_after(std::chrono::seconds(30));
        self->send(std::move(reply), keep_alive, version, head);
      });
    });
  }

  HttpReply too_large() const {
    return HttpReply::error(http::status::payload_too_large,
                            "request body over the limit of " + std::to_string(ctx_->settings.clients.max_body_bytes) + " bytes");
  }

  void upgrade() {
    const auto& req = parser_->get();
    std::string path(req.target());
    if (const auto q = path.find('?'); q != std::string::npos) path.resize(q);
    if (path != "/ws") return reply_and_close(HttpReply::error(http::status::not_found, "WebSocket endpoint is /ws"));
    const auto origin = req[http::field::origin];
    const auto host = req[http::field::host];
    const std::string refusal = origin_refusal({origin.data(), origin.size()}, {host.data(), host.size()}, ctx_->settings.origin);
    if (!refusal.empty()) {
      ctx_->log.warn(ctx_->clock.now(), "WebSocket origin refused").kv("remote", remote_).kv("origin", std::string(origin));
      return reply_and_close(HttpReply::error(http::status::forbidden, refusal));
    }
    auto session = ctx_->api.authenticate(req);
    if (!session) return reply_and_close(HttpReply::error(http::status::unauthorized, "log in before opening /ws"));
    const ClientId id = ctx_->next_client++;
    std::make_shared<WebSocketSession<Stream>>(std::move(stream_), id, std::move(*session), ctx_->lab,
                                               ctx_->settings.clients, ctx_->metrics)
        ->accept(parser_->release());
  }

  void reply_and_close(HttpReply reply) {
    ctx_->metrics.http_requests++;
    ctx_->metrics.http_errors_4xx++;
    send(std::move(reply), false, 11, false);
  }

  template <typename Body>
  void finish_headers(http::response<Body>& res, const HttpReply& reply, bool keep_alive) {
    res.set(http::field::server, "labodrone");
    res.set(http::field::content_type, reply.content_type);
    for (const auto& [name, value] : reply.headers) res.set(name, value);
    res.keep_alive(keep_alive);
  }

  void send(HttpReply reply, bool keep_alive, unsigned version, bool head) {
    if (reply.file) {
      http::file_body::value_type body;
      beast::error_code ec;
      body.open(reply.file->string().c_str(), beast::file_mode::scan, ec);
      if (!ec) {
        auto res = std::make_shared<http::response<http::file_body>>(http::status::ok, version);
        finish_headers(*res, reply, keep_alive);
        res->content_length(body.size());
        if (!head) res->body() = std::move(body);
        return write(res, head);
      }
      reply = HttpReply::error(http::status::not_found, "cannot open the file");
    }
    auto res = std::make_shared<http::response<http::string_body>>(reply.status, version);
    finish_headers(*res, reply, keep_alive);
    res->body() = std::move(reply.body);
    res->prepare_payload();
    if (head) res->body().clear();
    write(res, head);
  }

  template <typename Message>
  void write(const std::shared_ptr<Message>& res, bool head) {
    if (head) {
      auto sr = std::make_shared<http::response_serializer<typename Message::body_type>>(*res);
      http::async_write_header(stream_, *sr, [self = self(), res, sr](beast::error_code ec, std::size_t) {
        self->on_write(ec, res->need_eof());
      });
      return;
    }
    http::async_write(stream_, *res, [self = self(), res](beast::error_code ec, std::size_t) {
      self->on_write(ec, res->need_eof());
    });
  }

  void on_write(beast::error_code ec, bool close_after) {
    if (ec || close_after) return close();
    do_read();
  }

  void close() {
    beast::error_code ignored;
    beast::get_lowest_layer(stream_).socket().shutdown(tcp::socket::shutdown_send, ignored);
  }

  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<ServerContext> ctx_;
  std::string remote_;
};

}  // namespace

void start_http_session(tcp::socket&& socket, std::shared_ptr<ServerContext> ctx) {
  if (ctx->tls) {
    TlsStream stream(std::move(socket), *ctx->tls);
    std::make_shared<HttpSession<TlsStream>>(std::move(stream), std::move(ctx))->run();
    return;
  }
  std::make_shared<HttpSession<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), std::move(ctx))->run();
}

}  // namespace labo::server
