#include "server/api/rest_api.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <variant>

#include "server/app_config.hpp"
#include "server/auth/permissions.hpp"

namespace labo {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

constexpr const char* kCookie = "labo_session";

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

HttpReply ok_json(const json& j) { return HttpReply::json(http::status::ok, j.dump()); }

HttpReply method_not_allowed(const std::string& allowed) {
  HttpReply r = HttpReply::error(http::status::method_not_allowed, "method not allowed here; allowed: " + allowed);
  r.headers.emplace_back("Allow", allowed);
  return r;
}

bool safe_file_name(const std::string& name) {
  if (name.empty() || name.size() > 128 || name[0] == '.') return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) return false;
  return true;
}

}  // namespace

RestApi::RestApi(const ServerSettings& settings, std::filesystem::path config_file, SessionStore& sessions,
                 RemoteLab& lab, ServerMetrics& metrics, const Clock& clock)
    : settings_(settings),
      config_file_(std::move(config_file)),
      sessions_(sessions),
      lab_(lab),
      metrics_(metrics),
      clock_(clock),
      uploads_(settings.instruments_dir),
      labs_(settings.multi_lab.labs_file.empty()
                ? LabDirectory()
                : LabDirectory(settings.multi_lab.labs_file, settings.multi_lab.lab_id)) {}

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
  return sessions_.authenticate(token, clock_.now());
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
  const int code = static_cast<int>(reply.status);
  if (code >= 500) metrics_.http_errors_5xx++;
  else if (code >= 400) metrics_.http_errors_4xx++;
  return reply;
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
  const auto need = [&](Permission p) { return role_may(session->role, p); };
  const auto forbidden = [&] {
    return HttpReply::error(http::status::forbidden, "role " + to_string(session->role) + " may not do this");
  };
  const bool has_body = m == http::verb::post || m == http::verb::put;
  if (has_body && !req.body().empty() && !is_json(req))
    return HttpReply::error(http::status::unsupported_media_type, "send the body as application/json");

  if (path == "/api/logout") {
    if (m != http::verb::post) return method_not_allowed("POST");
    sessions_.logout(session->token);
    HttpReply r = ok_json({{"logged_out", session->user}});
    r.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict");
    return r;
  }
  if (path == "/api/me") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return ok_json({{"user", session->user}, {"role", to_string(session->role)}});
  }
  if (path == "/api/labs") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return HttpReply::json(http::status::ok, labs_.json());
  }
  if (path == "/api/status") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return status();
  }
  if (path == "/api/config") {
    if (!need(Permission::Administer)) return forbidden();
    if (m == http::verb::get) return get_config();
    if (m == http::verb::put) return put_config(req);
    return method_not_allowed("GET, PUT");
  }
  if (path == "/api/instruments") {
    if (m == http::verb::get) return instruments();
    if (m != http::verb::post) return method_not_allowed("GET, POST");
    if (!need(Permission::Administer)) return forbidden();
    return add_instrument(req);
  }
  if (path.rfind("/api/instruments/", 0) == 0) {
    if (m != http::verb::delete_) return method_not_allowed("DELETE");
    if (!need(Permission::Administer)) return forbidden();
    const std::string id = path.substr(17);
    if (!InstrumentStore::valid_id(id)) return HttpReply::error(http::status::bad_request, "invalid instrument id '" + id + "'");
    for (const auto& i : lab_.flight().instruments())
      if (i.id == id) return HttpReply::error(http::status::conflict, "instrument '" + id + "' is part of the lab description");
    if (!uploads_.remove(id)) return HttpReply::error(http::status::not_found, "no uploaded instrument '" + id + "'");
    return ok_json({{"deleted", id}});
  }
  if (path == "/api/users") {
    if (m != http::verb::get) return method_not_allowed("GET");
    if (!need(Permission::ViewSessions)) return forbidden();
    json users = json::array(), sessions = json::array();
    for (const auto& u : sessions_.users()) users.push_back({{"name", u.name}, {"role", to_string(u.role)}});
    const double now = clock_.now();
    for (const auto& s : sessions_.sessions(now))
      sessions.push_back({{"user", s.user}, {"role", to_string(s.role)}, {"age_s", now - s.created_s}, {"idle_s", now - s.last_seen_s}});
    return ok_json({{"users", users}, {"sessions", sessions}, {"control", json::parse(lab_.control_state_json())}});
  }
  if (path == "/api/recordings") {
    if (m != http::verb::get) return method_not_allowed("GET");
    if (!need(Permission::Administer)) return forbidden();
    return recordings();
  }
  if (path.rfind("/api/recordings/", 0) == 0) {
    if (m != http::verb::get) return method_not_allowed("GET");
    if (!need(Permission::Administer)) return forbidden();
    return recording(path.substr(16));
  }
  if (path == "/metrics") {
    if (m != http::verb::get) return method_not_allowed("GET");
    if (!need(Permission::Administer)) return forbidden();
    return metrics_text();
  }
  return HttpReply::error(http::status::not_found, "no route " + path);
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
  const LoginResult r = sessions_.login(j["user"], j["password"], remote, clock_.now());
  if (r.outcome == LoginOutcome::RateLimited) {
    metrics_.rate_limited++;
    HttpReply reply = HttpReply::error(http::status::too_many_requests, "too many login attempts from " + remote + ": wait a minute");
    reply.headers.emplace_back("Retry-After", "60");
    return reply;
  }
  if (r.outcome != LoginOutcome::Ok) {
    metrics_.logins_failed++;
    return HttpReply::error(http::status::unauthorized, "unknown user or wrong password");
  }
  metrics_.logins_ok++;
  HttpReply reply = ok_json({{"user", r.session.user}, {"role", to_string(r.session.role)}, {"token", r.session.token}});
  reply.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=" + r.session.token + "; Path=/; HttpOnly; SameSite=Strict");
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
                  {"video_fps", t.video_fps},
                  {"pose", {{"x", t.pose.x_m}, {"y", t.pose.y_m}, {"z", t.pose.z_m}, {"yaw", t.pose.yaw_rad}}},
                  {"clients", lab_.client_count()},
                  {"control", json::parse(lab_.control_state_json())}});
}

HttpReply RestApi::get_config() {
  std::ifstream in(config_file_);
  if (!in) return HttpReply::error(http::status::internal_server_error, "cannot read " + config_file_.string());
  std::stringstream text;
  text << in.rdbuf();
  return HttpReply::json(http::status::ok, text.str());
}

HttpReply RestApi::put_config(const HttpRequest& req) {
  const json j = json::parse(req.body(), nullptr, false);
  if (j.is_discarded()) return HttpReply::error(http::status::bad_request, "malformed JSON");
  if (!j.is_object()) return HttpReply::error(http::status::bad_request, "expected the whole configuration as a JSON object");
  try {
    // The same validation as at start-up: types, ranges, unknown keys, users' hashes.
    const ConfigDocument doc = ConfigDocument::parse(req.body(), "PUT /api/config");
    read_app_config(doc.root(), config_file_.parent_path());
  } catch (const ConfigError& e) {
    return HttpReply::error(http::status::unprocessable_entity, e.what());
  }
  const std::filesystem::path tmp = config_file_.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) return HttpReply::error(http::status::internal_server_error, "cannot write " + tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, config_file_, ec);  // atomic: readers see the old file or the new one
  if (ec) return HttpReply::error(http::status::internal_server_error, "cannot replace " + config_file_.string() + ": " + ec.message());
  return ok_json({{"saved", config_file_.string()}, {"restart_required", true}});
}

HttpReply RestApi::instruments() {
  json lab = json::array(), uploaded = json::array();
  for (const auto& i : lab_.flight().instruments())
    lab.push_back({{"id", i.id}, {"name", i.name}, {"width_m", i.width_m}, {"height_m", i.height_m}});
  for (const auto& u : uploads_.list())
    uploaded.push_back({{"id", u.id}, {"name", u.name}, {"width_m", u.width_m}, {"height_m", u.height_m},
                        {"position_m", {u.x_m, u.y_m, u.z_m}}, {"yaw_deg", u.yaw_deg}, {"texture_corners", u.texture_corners}});
  return ok_json({{"lab", lab}, {"uploaded", uploaded}});
}

HttpReply RestApi::add_instrument(const HttpRequest& req) {
  std::vector<std::string> reserved;
  for (const auto& i : lab_.flight().instruments()) reserved.push_back(i.id);
  auto result = uploads_.add(req.body(), reserved);
  if (auto* err = std::get_if<InstrumentError>(&result)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
  const auto& u = std::get<UploadedInstrument>(result);
  return HttpReply::json(http::status::created, json{{"id", u.id}, {"width_px", u.width_px}, {"height_px", u.height_px},
                                                     {"texture_corners", u.texture_corners}}.dump());
}

HttpReply RestApi::recordings() {
  json list = json::array();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(settings_.recordings_dir, ec)) {
    if (!entry.is_regular_file() || !safe_file_name(entry.path().filename().string())) continue;
    list.push_back({{"name", entry.path().filename().string()}, {"bytes", entry.file_size()},
                    {"url", "/api/recordings/" + entry.path().filename().string()}});
  }
  return ok_json({{"recordings", list}});
}

HttpReply RestApi::recording(const std::string& name) {
  if (!safe_file_name(name)) return HttpReply::error(http::status::bad_request, "invalid recording name '" + name + "'");
  const auto file = settings_.recordings_dir / name;
  if (!std::filesystem::is_regular_file(file)) return HttpReply::error(http::status::not_found, "no recording '" + name + "'");
  HttpReply r;
  r.content_type = "application/octet-stream";
  r.file = file;
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + name + "\"");
  return r;
}

HttpReply RestApi::metrics_text() {
  const FlightTelemetry t = lab_.flight().telemetry();
  std::ostringstream extra;
  extra << "# HELP labodrone_battery_percent Drone battery.\n# TYPE labodrone_battery_percent gauge\n"
        << "labodrone_battery_percent " << t.battery_percent << "\n"
        << "# HELP labodrone_link_quality Wi-Fi link quality 0..1.\n# TYPE labodrone_link_quality gauge\n"
        << "labodrone_link_quality " << t.link_quality << "\n"
        << "# HELP labodrone_video_fps Frames per second from the drone.\n# TYPE labodrone_video_fps gauge\n"
        << "labodrone_video_fps " << t.video_fps << "\n";
  HttpReply r = HttpReply::json(http::status::ok, metrics_.prometheus_text(extra.str()));
  r.content_type = "text/plain; version=0.0.4";
  return r;
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

}  // namespace labo
