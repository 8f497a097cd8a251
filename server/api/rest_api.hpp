#pragma once
// The HTTP routes: login/logout, the admin REST API, /metrics and the static pages. Every request
// is authenticated from the session cookie or a Bearer token and checked against the role's
// permissions; every refusal is a JSON error with its status. Runs on the connection's strand.
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include "core/time.hpp"
#include "server/api/face_registrar.hpp"
#include "server/api/http_reply.hpp"
#include "server/api/instrument_store.hpp"
#include "server/api/lab_directory.hpp"
#include "server/api/people_store.hpp"
#include "server/api/rest_support.hpp"
#include "server/audit/audit_log.hpp"
#include "server/auth/session_store.hpp"
#include "server/lab/remote_lab.hpp"
#include "server/lab/server_metrics.hpp"
#include "server/server_settings.hpp"

namespace labo::server {

class RestApi {
 public:
  RestApi(const ServerSettings& settings, std::filesystem::path config_file, SessionStore& sessions, RemoteLab& lab,
          ServerMetrics& metrics, const Clock& clock, AuditLog& audit);

  HttpReply handle(const HttpRequest& req, const std::string& remote_address);
  // The session a request (or WebSocket upgrade) carries, if valid.
  std::optional<SessionInfo> authenticate(const HttpRequest& req);
  // Stops the face registration worker (what waits is refused); before the io threads are gone.
  void stop_workers();

 private:
  HttpReply route(const HttpRequest& req, const std::string& path, const std::string& remote);
  HttpReply route_admin(const HttpRequest& req, const std::string& path, const SessionInfo& session);
  HttpReply login(const HttpRequest& req, const std::string& remote);
  HttpReply users(const SessionInfo& session);
  HttpReply route_users(const HttpRequest& req, const std::string& path, const SessionInfo& session);
  HttpReply add_user(const HttpRequest& req, const SessionInfo& session);
  HttpReply change_user(const HttpRequest& req, const std::string& name, const SessionInfo& session);
  HttpReply remove_user(const std::string& name, const SessionInfo& session);
  // Reads the config file, lets `edit` change its JSON (or refuse), validates and replaces the file,
  // applies the users; answers `answer` with `status`.
  HttpReply edit_users(const std::function<std::optional<HttpReply>(nlohmann::json&)>& edit,
                       boost::beast::http::status status, nlohmann::json answer);
  // New accounts at once; the sessions and connections of removed or re-roled users end.
  void apply_users(const std::vector<UserAccount>& users);
  HttpReply stop(const HttpRequest& req, const SessionInfo& session, MissionCommandKind kind);
  HttpReply audit_page(const HttpRequest& req);
  HttpReply status();
  HttpReply get_config();
  HttpReply put_config(const HttpRequest& req, const SessionInfo& session);
  HttpReply save_config(const HttpRequest& req);
  HttpReply instruments();
  HttpReply route_instruments(const HttpRequest& req, const std::string& path, const SessionInfo& session);
  HttpReply add_instrument(const HttpRequest& req, const SessionInfo& session);
  HttpReply place_instrument(const HttpRequest& req, const std::string& id, const SessionInfo& session);
  HttpReply delete_instrument(const std::string& id, const SessionInfo& session);
  // Validated against the lab's outline, then handed to the flight software; the refusal otherwise.
  std::optional<HttpReply> place_upload(const UploadedInstrument& u);
  // At start: the stored uploads that were placed, placed again.
  void place_stored_instruments();
  HttpReply recordings();
  HttpReply recording(const std::string& name);
  // replay_routes.cpp: a recording played in the page, its status, its stop.
  HttpReply start_replay(const HttpRequest& req, const std::string& name, const SessionInfo& session);
  HttpReply route_replay(const HttpRequest& req, const SessionInfo& session);
  HttpReply metrics_text();
  // The teacher's routes (teacher_routes.cpp): registered people, the person face-follow follows,
  // ending a student's turn.
  HttpReply route_teacher(const HttpRequest& req, const std::string& path, const SessionInfo& session);
  HttpReply people();
  HttpReply register_person(const HttpRequest& req, const SessionInfo& session);
  HttpReply delete_person(const std::string& name, const SessionInfo& session);
  HttpReply followed_person();
  HttpReply follow_person(const HttpRequest& req, const SessionInfo& session);
  HttpReply choose_followed(const HttpRequest& req);
  HttpReply end_turn(const HttpRequest& req, const SessionInfo& session);
  void count_errors(const HttpReply& reply);
  HttpReply static_file(const std::string& path);
  // "; Path=/; HttpOnly; SameSite=Strict", and "; Secure" over TLS.
  std::string cookie_attributes() const;
  // An administrative action into the audit log, with the HTTP status of its answer.
  void audit(const SessionInfo& session, const std::string& action, const std::string& target, const HttpReply& reply,
             const std::string& detail = {});

  ServerSettings settings_;
  std::filesystem::path config_file_;
  SessionStore& sessions_;
  RemoteLab& lab_;
  ServerMetrics& metrics_;
  const Clock& clock_;
  AuditLog& audit_;
  InstrumentStore uploads_;
  LabDirectory labs_;
  std::mutex config_mutex_;  // one change of the config file at a time
  std::mutex instruments_mutex_;  // one change of the instruments at a time; removed_instruments_
  std::set<std::string> removed_instruments_;  // placed, then removed: ids the flight software keeps until a restart
  // With settings.people: the registered people and their registration worker (declared last:
  // stopped first, while everything its jobs' answers use still exists).
  std::unique_ptr<PeopleStore> people_;
  std::unique_ptr<FaceRegistrar> registrar_;
};

}  // namespace labo::server
