#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <variant>

#include "server/api/rest_api.hpp"
#include "server/api/config_file.hpp"
#include "server/auth/permissions.hpp"

// The routes only an admin may use: configuration, instruments, recordings, metrics, the audit log.
namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

HttpReply RestApi::route_admin(const HttpRequest& req, const std::string& path, const SessionInfo& session) {
  const http::verb m = req.method();
  const bool known = path == "/api/config" || path == "/api/instruments" || path.rfind("/api/instruments/", 0) == 0 ||
                     path == "/api/users" || path == "/api/recordings" || path.rfind("/api/recordings/", 0) == 0 || path == "/api/replay" ||
                     path == "/metrics" || path == "/api/audit" || path.rfind("/api/users/", 0) == 0 ||
                     path.rfind("/api/sessions/", 0) == 0;
  if (!known) return HttpReply::error(http::status::not_found, "no route " + path);
  if (!role_may(session.role, Permission::Administer))
    return HttpReply::error(http::status::forbidden, "role " + to_string(session.role) + " may not do this");
  if (path == "/api/config") {
    if (m == http::verb::get) return get_config();
    if (m == http::verb::put) return put_config(req, session);
    return method_not_allowed("GET, PUT");
  }
  if (path == "/api/instruments" || path.rfind("/api/instruments/", 0) == 0) return route_instruments(req, path, session);
  if (path == "/api/users" || path.rfind("/api/users/", 0) == 0 || path.rfind("/api/sessions/", 0) == 0)
    return route_users(req, path, session);
  if (path == "/api/recordings") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return recordings();
  }
  if (path.rfind("/api/recordings/", 0) == 0) {
    const std::string rest = path.substr(16);
    if (const auto slash = rest.find('/'); slash != std::string::npos) {
      if (rest.substr(slash) != "/replay") return HttpReply::error(http::status::not_found, "no route " + path);
      if (m != http::verb::post) return method_not_allowed("POST");
      const std::string name = rest.substr(0, slash);
      const HttpReply reply = start_replay(req, name, session);
      audit(session, "replay_start", name, reply);
      return reply;
    }
    if (m != http::verb::get) return method_not_allowed("GET");
    return recording(rest);
  }
  if (path == "/api/replay") return route_replay(req, session);
  if (path == "/api/audit") {
    if (m != http::verb::get) return method_not_allowed("GET");
    return audit_page(req);
  }
  if (m != http::verb::get) return method_not_allowed("GET");
  return metrics_text();
}

HttpReply RestApi::audit_page(const HttpRequest& req) {
  const std::string_view target(req.target().data(), req.target().size());
  const auto offset = query_integer(target, "offset", 0, 0, 1L << 40);
  if (const auto* refused = std::get_if<HttpReply>(&offset)) return *refused;
  const auto limit = query_integer(target, "limit", 50, 1, 500);
  if (const auto* refused = std::get_if<HttpReply>(&limit)) return *refused;
  const AuditPage page = audit_.read(static_cast<std::size_t>(std::get<long>(offset)), static_cast<std::size_t>(std::get<long>(limit)));
  json entries = json::array();
  for (const std::string& line : page.lines) entries.push_back(json::parse(line, nullptr, false));
  return ok_json({{"total", page.total}, {"offset", std::get<long>(offset)}, {"limit", std::get<long>(limit)}, {"entries", entries}});
}

HttpReply RestApi::get_config() {
  std::ifstream in(config_file_);
  if (!in) return HttpReply::error(http::status::internal_server_error, "cannot read " + config_file_.string());
  std::stringstream text;
  text << in.rdbuf();
  return HttpReply::json(http::status::ok, text.str());
}

HttpReply RestApi::put_config(const HttpRequest& req, const SessionInfo& session) {
  HttpReply reply = save_config(req);
  audit(session, "config_put", config_file_.filename().string(), reply);
  return reply;
}

HttpReply RestApi::save_config(const HttpRequest& req) {
  const json j = json::parse(req.body(), nullptr, false);
  if (j.is_discarded()) return HttpReply::error(http::status::bad_request, "malformed JSON");
  if (!j.is_object()) return HttpReply::error(http::status::bad_request, "expected the whole configuration as a JSON object");
  std::lock_guard lock(config_mutex_);
  auto before = read_config_json(config_file_);
  if (auto* err = std::get_if<ConfigFileError>(&before)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
  auto written = replace_config(config_file_, j);
  if (auto* err = std::get_if<ConfigFileError>(&written)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
  json applied = json::array(), restart = json::array();
  for (const std::string& key : changed_keys(std::get<json>(before), j)) (key == "server.users" ? applied : restart).push_back(key);
  if (!applied.empty()) apply_users(std::get<AppConfig>(written).server.users);
  return ok_json({{"saved", config_file_.string()}, {"applied", applied}, {"restart_required", restart}});
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
        << "labodrone_video_fps " << t.video_fps << "\n"
        << "# HELP labodrone_slam_keyframes Keyframes in the SLAM map (at most slam.max_keyframes).\n"
        << "# TYPE labodrone_slam_keyframes gauge\n"
        << "labodrone_slam_keyframes " << t.slam_keyframes << "\n"
        << "# HELP labodrone_slam_map_mib Memory the SLAM map holds (MiB).\n# TYPE labodrone_slam_map_mib gauge\n"
        << "labodrone_slam_map_mib " << t.slam_map_mib << "\n";
  HttpReply r = HttpReply::json(http::status::ok, metrics_.prometheus_text(extra.str()));
  r.content_type = "text/plain; version=0.0.4";
  return r;
}

}  // namespace labo::server
