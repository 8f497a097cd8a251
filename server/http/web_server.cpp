#include "server/http/web_server.hpp"

#include <boost/asio/signal_set.hpp>
#include <boost/asio/strand.hpp>

#include "server/http/http_session.hpp"
#include "server/http/server_context.hpp"

namespace labo::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

void accept_next(const std::shared_ptr<ServerContext>& ctx) {
  // Each connection gets its own strand: its handlers never run concurrently, whatever the threads.
  ctx->acceptor.async_accept(asio::make_strand(ctx->io), [ctx](boost::system::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || !ctx->acceptor.is_open()) return;
    if (!ec) start_http_session(std::move(socket), ctx);
    accept_next(ctx);
  });
}

void tick_next(const std::shared_ptr<ServerContext>& ctx) {
  ctx->tick_timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / ctx->settings.video.telemetry_hz)));
  ctx->tick_timer.async_wait([ctx](boost::system::error_code ec) {
    if (ec) return;
    ctx->lab->tick();
    ctx->sessions.save_if_changed(unix_now_s());
    ctx->heap_release.tick(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
    tick_next(ctx);
  });
}

}  // namespace

WebServer::WebServer(ServerSettings settings, std::filesystem::path config_file, FlightService& flight, Logger log)
    : io_(std::make_unique<asio::io_context>()),
      ctx_(std::make_shared<ServerContext>(*io_, std::move(settings), std::move(config_file), flight, std::move(log))) {}

WebServer::~WebServer() { shutdown(0.0); }

ServerMetrics& WebServer::metrics() { return ctx_->metrics; }

unsigned short WebServer::start() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(ctx_->settings.bind_address, ec);
  if (ec) throw std::runtime_error("bind address '" + ctx_->settings.bind_address + "' is not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(ctx_->settings.port));
  auto& acceptor = ctx_->acceptor;
  acceptor.open(endpoint.protocol());
  acceptor.set_option(asio::socket_base::reuse_address(true));
  acceptor.bind(endpoint, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + ctx_->settings.bind_address + ":" + std::to_string(ctx_->settings.port) +
                             ": " + ec.message());
  acceptor.listen(asio::socket_base::max_listen_connections);
  const unsigned short port = acceptor.local_endpoint().port();
  accept_next(ctx_);
  tick_next(ctx_);
  for (int i = 0; i < ctx_->settings.threads; ++i) threads_.emplace_back([ctx = ctx_] { ctx->io.run(); });
  const std::string scheme = ctx_->tls ? "https://" : "http://";
  ctx_->log.info(ctx_->clock.now(), "serving").kv("url", scheme + ctx_->settings.bind_address + ":" + std::to_string(port) + "/");
  return port;
}

void WebServer::run_until_signal() {
  asio::io_context signal_io;
  asio::signal_set signals(signal_io, SIGINT, SIGTERM);
  int received = 0;
  signals.async_wait([&](const boost::system::error_code&, int signal) { received = signal; });
  signal_io.run();
  ctx_->log.info(ctx_->clock.now(), "signal received: landing, then stopping").kv("signal", received);
  shutdown();
}

void WebServer::shutdown(double land_timeout_s) {
  if (stopped_.exchange(true)) return;
  // Land first, while the clients still receive the video and the stage changes.
  if (land_timeout_s > 0) ctx_->lab->flight().land_and_stop(land_timeout_s);
  asio::post(ctx_->io, [ctx = ctx_] {
    boost::system::error_code ignored;
    ctx->acceptor.close(ignored);
    ctx->tick_timer.cancel();
    ctx->lab->disconnect_all("server shutting down");
  });
  // Give the close frames a moment, then stop.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ctx_->io.stop();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
  ctx_->api.stop_workers();
  ctx_->sessions.save_if_changed(unix_now_s(), true);
}

}  // namespace labo::server
