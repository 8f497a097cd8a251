#pragma once
// The HTTP routes: login/logout, the admin REST API, /metrics and the static pages. Every request
// is authenticated from the session cookie or a Bearer token and checked against the role's
// permissions; every refusal is a JSON error with its status. Runs on the connection's strand.
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <filesystem>
#include <optional>
#include <string>

#include "core/time.hpp"
#include "server/api/http_reply.hpp"
#include "server/api/instrument_store.hpp"
#include "server/api/lab_directory.hpp"
#include "server/auth/session_store.hpp"
#include "server/lab/remote_lab.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo {

using HttpRequest = boost::beast::http::request<boost::beast::http::string_body>;

class RestApi {
 public:
  RestApi(const ServerSettings& settings, std::filesystem::path config_file, SessionStore& sessions, RemoteLab& lab,
          ServerMetrics& metrics, const Clock& clock);

  HttpReply handle(const HttpRequest& req, const std::string& remote_address);
  // The session a request (or WebSocket upgrade) carries, if valid.
  std::optional<SessionInfo> authenticate(const HttpRequest& req);

 private:
  HttpReply route(const HttpRequest& req, const std::string& path, const std::string& remote);
  HttpReply login(const HttpRequest& req, const std::string& remote);
  HttpReply status();
  HttpReply get_config();
  HttpReply put_config(const HttpRequest& req);
  HttpReply instruments();
  HttpReply add_instrument(const HttpRequest& req);
  HttpReply recordings();
  HttpReply recording(const std::string& name);
  HttpReply metrics_text();
  HttpReply static_file(const std::string& path);

  ServerSettings settings_;
  std::filesystem::path config_file_;
  SessionStore& sessions_;
  RemoteLab& lab_;
  ServerMetrics& metrics_;
  const Clock& clock_;
  InstrumentStore uploads_;
  LabDirectory labs_;
};

}  // namespace labo
