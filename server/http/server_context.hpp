#pragma once
// What every connection of one WebServer shares.
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <memory>

#include "core/log.hpp"
#include "core/time.hpp"
#include "server/api/rest_api.hpp"
#include "server/audit/audit_log.hpp"
#include "server/auth/session_store.hpp"
#include "server/lab/remote_lab.hpp"
#include "server/http/heap_release.hpp"
#include "server/http/tls_context.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

struct ServerContext {
  ServerContext(boost::asio::io_context& io_context, ServerSettings s, std::filesystem::path config_file,
                FlightService& flight, Logger l)
      : io(io_context),
        settings(std::move(s)),
        log(std::move(l)),
        acceptor(io),
        tick_timer(io),
        tls(make_tls_context(settings.tls)),
        audit(settings.audit_log),
        sessions(settings.users, settings.clients.session_idle_timeout_s, settings.clients.login_attempts_per_min,
                 settings.sessions_file),
        lab(std::make_shared<RemoteLab>(flight, settings, metrics, clock, audit, log.child("lab"))),
        api(settings, std::move(config_file), sessions, *lab, metrics, clock, audit) {
    if (!settings.multi_lab.session_key_file.empty())
      sessions.share_with(SessionSigner::from_key_file(settings.multi_lab.session_key_file));
  }

  // Owned by the WebServer and destroyed after the last handler lets go of this context.
  boost::asio::io_context& io;
  ServerSettings settings;
  Logger log;
  SteadyClock clock;
  ServerMetrics metrics;
  boost::asio::ip::tcp::acceptor acceptor;
  boost::asio::steady_timer tick_timer;
  HeapRelease heap_release;  // on the tick
  std::unique_ptr<boost::asio::ssl::context> tls;  // null: plain HTTP
  AuditLog audit;
  SessionStore sessions;
  std::shared_ptr<RemoteLab> lab;
  RestApi api;
  std::atomic<ClientId> next_client{1};
};

}  // namespace labo::server
