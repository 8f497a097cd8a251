#include "server/static_http_server.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace labo {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

std::string content_type_for(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

namespace {

http::response<http::string_body> make_response(const http::request<http::string_body>& req,
                                                const std::filesystem::path& web_root) {
  http::response<http::string_body> res;
  res.version(req.version());
  res.keep_alive(false);
  res.set(http::field::server, "labodrone");
  auto json_error = [&](http::status status, const std::string& message) {
    res.result(status);
    res.set(http::field::content_type, "application/json");
    res.body() = "{\"error\":\"" + message + "\"}";
  };
  const std::string target(req.target());
  if (req.method() != http::verb::get) {
    json_error(http::status::method_not_allowed, "only GET is served");
  } else if (target == "/api/health") {
    res.result(http::status::ok);
    res.set(http::field::content_type, "application/json");
    res.body() = "{\"status\":\"ok\"}";
  } else if (target.find("..") != std::string::npos || target.empty() || target[0] != '/') {
    json_error(http::status::bad_request, "invalid path");
  } else {
    std::filesystem::path file = web_root / (target == "/" ? "index.html" : target.substr(1));
    std::ifstream in(file, std::ios::binary);
    if (!in) {
      json_error(http::status::not_found, "no such file: " + target);
    } else {
      std::stringstream body;
      body << in.rdbuf();
      res.result(http::status::ok);
      res.set(http::field::content_type, content_type_for(file));
      res.body() = body.str();
    }
  }
  res.prepare_payload();
  return res;
}

class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket socket, const std::filesystem::path& web_root)
      : stream_(std::move(socket)), web_root_(web_root) {}

  void start() {
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

 private:
  void on_read(beast::error_code ec) {
    if (ec) return;
    response_ = make_response(request_, web_root_);
    http::async_write(stream_, response_, [self = shared_from_this()](beast::error_code, std::size_t) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  http::response<http::string_body> response_;
  std::filesystem::path web_root_;
};

void accept_loop(tcp::acceptor& acceptor, const std::filesystem::path& web_root) {
  acceptor.async_accept([&acceptor, &web_root](beast::error_code ec, tcp::socket socket) {
    if (ec) return;
    std::make_shared<Connection>(std::move(socket), web_root)->start();
    accept_loop(acceptor, web_root);
  });
}

}  // namespace

int run_static_http_server(const StaticHttpServerOptions& options) {
  asio::io_context io;
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(options.bind_address, ec);
  if (ec) throw std::runtime_error("--bind: '" + options.bind_address + "' is not an IP address");
  tcp::acceptor acceptor(io);
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(options.port));
  acceptor.open(endpoint.protocol());
  acceptor.set_option(asio::socket_base::reuse_address(true));
  acceptor.bind(endpoint, ec);
  if (ec) throw std::runtime_error("cannot listen on " + options.bind_address + ":" + std::to_string(options.port) + ": " + ec.message());
  acceptor.listen();
  accept_loop(acceptor, options.web_root);

  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code&, int) { io.stop(); });
  std::cout << "LaboDrone is serving on http://" << options.bind_address << ":" << options.port << "/" << std::endl;
  io.run();
  return 0;
}

}  // namespace labo
