#include "server/api/rest_api.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <variant>

#include "core/candide3.hpp"
#include "server/api/drone_routes.hpp"
#include "server/api/video_routes.hpp"
#include "server/auth/permissions.hpp"

namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

constexpr const char* kCookie = "labo_session";

HttpReply forbidden(const SessionInfo& session) {
  return HttpReply::error(http::status::forbidden, "role " + to_string(session.role) + " may not do this");
}

std::string cookie_value(std::string_view header, std::string_view name) {
  std::size_t pos = 0;
  while (pos < header.size()) {
    std::size_t end = header.find(';', pos);
    if (end == std::string_view::npos) end = header.size();
    std::string_view part = header.substr(pos, end - pos);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name && part[name.size()] == '=')
      return std::string(part.substr(name.size() + 1));
    pos = end + 1;
  }
  return {};
}

bool is_json(const HttpRequest& req) {
  const auto ct = req[http::field::content_type];
  return ct.substr(0, 16) == "application/json";
}


}  // namespace

RestApi::RestApi(const ServerSettings& settings, std::filesystem::path config_file, SessionStore& sessions,
                 RemoteLab& lab, ServerMetrics& metrics, const Clock& clock, AuditLog& audit)
    : settings_(settings),
      config_file_(std::move(config_file)),
      sessions_(sessions),
      lab_(lab),
      metrics_(metrics),
      clock_(clock),
      audit_(audit),
      uploads_(settings.instruments_dir),
      labs_(settings.multi_lab.labs_file.empty()
                ? LabDirectory()
                : LabDirectory(settings.multi_lab.labs_file, settings.multi_lab.lab_id)) {
  if (settings.people.enabled()) {
    const auto units = static_cast<int>(Candide3Model::load(settings.people.face.model).shape_units().size());
    people_ = std::make_unique<PeopleStore>(settings.people.face.people_dir, units);
    registrar_ = std::make_unique<FaceRegistrar>(settings.people, *people_);
    if (!settings.people.face.teacher.empty()) lab_.followed_person().set(people_->load(settings.people.face.teacher));
  }
  place_stored_instruments();
}

void RestApi::stop_workers() {
  if (registrar_) registrar_->stop();
}

std::optional<SessionInfo> RestApi::authenticate(const HttpRequest& req) {
  std::string token;
  const auto auth = req[http::field::authorization];
  if (auth.substr(0, 7) == "Bearer ") token = std::string(auth.substr(7));
  if (token.empty()) {
    const auto cookie = req[http::field::cookie];
    token = cookie_value(std::string_view(cookie.data(), cookie.size()), kCookie);
  }
  if (token.empty()) {
    // Scripts and the WebSocket API may pass ?token= on /ws.
    const std::string target(req.target());
    const auto q = target.find("token=");
    if (q != std::string::npos && target.substr(0, 3) == "/ws") token = target.substr(q + 6, target.find('&', q) - q - 6);
  }
  if (token.empty() || token.size() > 256) return std::nullopt;  // a signed token names its user (session_signer.hpp)
  return sessions_.authenticate(token, unix_now_s());
}

HttpReply RestApi::handle(const HttpRequest& req, const std::string& remote) {
  metrics_.http_requests++;
  std::string path(req.target());
  if (const auto q = path.find('?'); q != std::string::npos) path.resize(q);
  HttpReply reply;
  try {
    reply = route(req, path, remote);
  } catch (const std::exception& e) {
    reply = HttpReply::error(http::status::internal_server_error, std::string("internal error: ") + e.what());
  }
  if (reply.deferred) {
    // Counted when the final reply is known.
    reply.deferred = [this, work = std::move(reply.deferred)](std::function<void(HttpReply)> done) {
      work([this, done = std::move(done)](HttpReply final_reply) {
        count_errors(final_reply);
        done(std::move(final_reply));
      });
    };
    return reply;
  }
  count_errors(reply);
  return reply;
}

void RestApi::count_errors(const HttpReply& reply) {
  const int code = static_cast<int>(reply.status);
  if (code >= 500) metrics_.http_errors_5xx++;
  else if (code >= 400) metrics_.http_errors_4xx++;
}

HttpReply RestApi::route(const HttpRequest& req, const std::string& path, const std::string& remote) {
  const http::verb m = req.method();
  if (path == "/api/health") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return ok_json({{"status", "ok"}, {"uptime_s", clock_.now()}, {"link_state", lab_.flight().telemetry().link_state}});
  }
  if (path == "/api/login") {
    if (m != http::verb::post) return method_not_allowed("POST");
    return login(req, remote);
  }
  const bool api = path.rfind("/api/", 0) == 0 || path == "/metrics";
  if (!api) {
    if (m != http::verb::get && m != http::verb::head) return method_not_allowed("GET, HEAD");
    return static_file(path);
  }
  // Everything below needs a session.
  const auto session = authenticate(req);
  if (!session) return HttpReply::error(http::status::unauthorized, "log in first: missing, unknown or expired session");
  if (path == "/api/people" || path.rfind("/api/people/", 0) == 0 || path == "/api/face_follow" || path == "/api/control/end_turn")
    return route_teacher(req, path, *session);  // its photos come as multipart/form-data
  const bool has_body = m == http::verb::post || m == http::verb::put;
  if (has_body && !req.body().empty() && !is_json(req))
    return HttpReply::error(http::status::unsupported_media_type, "send the body as application/json");

  if (path == "/api/logout") {
    if (m != http::verb::post) return method_not_allowed("POST");
    sessions_.logout(session->token);
    HttpReply r = ok_json({{"logged_out", session->user}});
    r.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=; Max-Age=0" + cookie_attributes());
    return r;
  }
  if (path == "/api/me") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return ok_json({{"user", session->user}, {"role", to_string(session->role)}, {"session", session->id}});
  }
  if (path == "/api/labs") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return HttpReply::json(http::status::ok, labs_.json());
  }
  if (path == "/api/status") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return status();
  }
  if (auto video = video_route(req, path, session->role, lab_.flight(), settings_.video.low_rendition_kbps)) {
    // The drone's bit rate is every viewer's picture: who asked for which, refusals included, is kept.
    if (path == "/api/video/bitrate" && m == http::verb::put) audit(*session, "video_bitrate", requested_kbps(req), *video);
    return *video;
  }
  if (auto drone = drone_route(req, path, session->role, lab_.flight())) {
    // Where the drone is decides where it flies next: who said so is kept, refusals included.
    if (req.method() == http::verb::post) audit(*session, "drone_set_down", "platform", *drone);
    return *drone;
  }
  if (path == "/api/stop" || path == "/api/emergency_stop") {
    if (m != http::verb::post) return method_not_allowed("POST");
    return stop(req, *session, path == "/api/stop" ? MissionCommandKind::Stop : MissionCommandKind::EmergencyStop);
  }
  if (path == "/api/instruments" && m == http::verb::get) return instruments();
  if (path == "/api/users" && m == http::verb::get) {
    if (!role_may(session->role, Permission::ViewSessions)) return forbidden(*session);
    return users(*session);
  }
  return route_admin(req, path, *session);
}

HttpReply RestApi::users(const SessionInfo&) {
  json users = json::array(), sessions = json::array();
  for (const auto& u : sessions_.users()) users.push_back({{"name", u.name}, {"role", to_string(u.role)}});
  const double now = unix_now_s();
  for (const auto& s : sessions_.sessions(now))
    sessions.push_back({{"id", s.id}, {"user", s.user}, {"role", to_string(s.role)}, {"age_s", now - s.created_s},
                        {"idle_s", now - s.last_seen_s}});
  return ok_json({{"users", users}, {"sessions", sessions}, {"control", json::parse(lab_.control_state_json())}});
}

HttpReply RestApi::stop(const HttpRequest& req, const SessionInfo& session, MissionCommandKind kind) {
  if (!req.body().empty()) {
    auto body = json_object_body(req, {});
    if (auto* refused = std::get_if<HttpReply>(&body)) return *refused;
  }
  const RemoteLab::RestCommandResult r = lab_.stop_from_rest(session, kind);
  const json answer{{"command", to_string(kind)}, {"accepted", r.verdict.accepted}, {"reason", r.verdict.reason}};
  if (r.status == 403) return HttpReply::error(http::status::forbidden, r.verdict.reason);
  // The flight software's refusal (nothing flying to stop, say) is a conflict with the drone's state.
  if (!r.verdict.accepted) return HttpReply::error(http::status::conflict, to_string(kind) + " refused: " + r.verdict.reason);
  return ok_json(answer);
}

HttpReply RestApi::login(const HttpRequest& req, const std::string& remote) {
  if (!is_json(req)) return HttpReply::error(http::status::unsupported_media_type, "send the body as application/json");
  const json j = json::parse(req.body(), nullptr, false);
  if (j.is_discarded()) return HttpReply::error(http::status::bad_request, "malformed JSON");
  if (!j.is_object()) return HttpReply::error(http::status::bad_request, "expected a JSON object {\"user\", \"password\"}");
  for (const auto& [key, v] : j.items())
    if (key != "user" && key != "password") return HttpReply::error(http::status::bad_request, "unknown field '" + key + "'");
  if (!j.contains("user") || !j["user"].is_string() || !j.contains("password") || !j["password"].is_string())
    return HttpReply::error(http::status::bad_request, "'user' and 'password' must be strings");
  const std::string user = j["user"];
  const LoginResult r = sessions_.login(user, j["password"], remote, unix_now_s());
  const auto audit_login = [&](bool accepted, const std::string& detail) {
    audit_.record({user, accepted ? to_string(r.session.role) : "", "login", remote, accepted, detail});
  };
  if (r.outcome == LoginOutcome::RateLimited) {
    metrics_.rate_limited++;
    audit_login(false, "rate limited");
    HttpReply reply = HttpReply::error(http::status::too_many_requests, "too many login attempts from " + remote + ": wait a minute");
    reply.headers.emplace_back("Retry-After", "60");
    return reply;
  }
  if (r.outcome != LoginOutcome::Ok) {
    metrics_.logins_failed++;
    audit_login(false, "unknown user or wrong password");
    return HttpReply::error(http::status::unauthorized, "unknown user or wrong password");
  }
  metrics_.logins_ok++;
  audit_login(true, "");
  HttpReply reply = ok_json({{"user", r.session.user}, {"role", to_string(r.session.role)}, {"token", r.session.token}});
  reply.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=" + r.session.token + cookie_attributes());
  return reply;
}

HttpReply RestApi::status() {
  const FlightTelemetry t = lab_.flight().telemetry();
  return ok_json({{"mission", t.mission},
                  {"stage", t.stage},
                  {"flying", t.flying},
                  {"battery_percent", t.battery_percent},
                  {"altitude_m", t.altitude_m},
                  {"link_state", t.link_state},
                  {"link_quality", t.link_quality},
                  {"source", to_string(t.source)},
                  {"unobserved_flight_s", t.unobserved_flight_s},
                  {"video_fps", t.video_fps},
                  {"pose", {{"x", t.pose.x_m}, {"y", t.pose.y_m}, {"z", t.pose.z_m}, {"yaw", t.pose.yaw_rad}}},
                  {"clients", lab_.client_count()},
                  {"control", json::parse(lab_.control_state_json())}});
}

HttpReply RestApi::static_file(const std::string& path) {
  if (path.empty() || path[0] != '/' || path.find("..") != std::string::npos || path.find('\\') != std::string::npos)
    return HttpReply::error(http::status::bad_request, "invalid path");
  std::filesystem::path file = settings_.web_root / (path == "/" ? "index.html" : path.substr(1));
  if (std::filesystem::is_directory(file)) file /= "index.html";
  if (!std::filesystem::is_regular_file(file)) return HttpReply::error(http::status::not_found, "no such file: " + path);
  HttpReply r;
  r.content_type = content_type_for(file);
  r.file = file;
  r.headers.emplace_back("Cache-Control", "no-cache");
  return r;
}

std::string RestApi::cookie_attributes() const {
  return std::string("; Path=/; HttpOnly; SameSite=Strict") + (settings_.tls.enabled() ? "; Secure" : "");
}

void RestApi::audit(const SessionInfo& session, const std::string& action, const std::string& target, const HttpReply& reply,
                    const std::string& detail) {
  const int code = static_cast<int>(reply.status);
  std::string what = detail;
  if (code >= 400) {
    const json body = json::parse(reply.body, nullptr, false);
    what = std::to_string(code) + ": " + (body.is_object() ? body.value("error", "") : std::string());
  }
  audit_.record({session.user, to_string(session.role), action, target, code < 400, what});
}

}  // namespace labo::server
