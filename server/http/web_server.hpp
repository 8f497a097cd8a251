#pragma once
// The LaboDrone web server: one listener, HTTP and WebSocket on one port, a strand per connection,
// N io_context threads, a periodic tick that drives the control queue and the telemetry broadcast.
// shutdown() lands the drone before it stops serving, so everyone watching sees the landing.
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/lab/flight_service.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

struct ServerContext;

class WebServer {
 public:
  WebServer(ServerSettings settings, std::filesystem::path config_file, FlightService& flight, Logger log);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Binds (port 0 picks a free one) and starts the threads; returns the bound port. Throws
  // std::runtime_error naming the address when it cannot listen.
  unsigned short start();
  // Blocks until SIGINT or SIGTERM, then shuts down.
  void run_until_signal();
  // Lands the drone (up to land_timeout_s), closes every client and stops the threads. Idempotent.
  void shutdown(double land_timeout_s = 15.0);

  ServerMetrics& metrics();

 private:
  // Declared first, destroyed last: destroying it releases the handlers that hold ctx_.
  std::unique_ptr<boost::asio::io_context> io_;
  std::shared_ptr<ServerContext> ctx_;
  std::vector<std::thread> threads_;
  std::atomic<bool> stopped_{false};
};

}  // namespace labo::server
