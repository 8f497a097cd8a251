#pragma once
// A minimal HTTP/1.1 server on Boost.Beast: static files from the web root and GET /api/health.
// The foundation's `labodrone serve`; the remote-lab server (issue #10) grows from here.
#include <filesystem>
#include <string>

namespace labo {

struct StaticHttpServerOptions {
  std::string bind_address = "127.0.0.1";
  int port = 8080;
  std::filesystem::path web_root;
};

// Serves until SIGINT or SIGTERM. Returns the process exit status; throws std::runtime_error when
// the address cannot be bound.
int run_static_http_server(const StaticHttpServerOptions& options);

// Content type from a file extension (".html" -> "text/html; charset=utf-8").
std::string content_type_for(const std::filesystem::path& file);

}  // namespace labo
