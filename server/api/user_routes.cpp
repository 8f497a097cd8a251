#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/config_file.hpp"
#include "server/api/rest_api.hpp"
#include "server/auth/password_hash.hpp"

// The admin's user and session management: users are added, removed, re-roled and given a new
// password in the configuration file itself (validated, replaced atomically) and applied at once;
// the sessions of a removed or re-roled user end, and their WebSockets close.
namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

constexpr std::size_t kMinPasswordLength = 8;

bool valid_user_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  return true;
}

// A refusal of the fields common to adding and changing a user, or empty.
std::optional<HttpReply> check_fields(const json& body) {
  if (body.contains("role") && (!body["role"].is_string() || (body["role"] != "student" && body["role"] != "teacher" && body["role"] != "admin")))
    return HttpReply::error(http::status::unprocessable_entity, "'role' must be student, teacher or admin");
  if (body.contains("password")) {
    if (!body["password"].is_string()) return bad_request("'password' must be a string");
    const std::size_t n = body["password"].get<std::string>().size();
    if (n < kMinPasswordLength || n > 256)
      return HttpReply::error(http::status::unprocessable_entity,
                              "'password' must be " + std::to_string(kMinPasswordLength) + " to 256 characters");
  }
  return std::nullopt;
}

json* find_user(json& doc, const std::string& name) {
  for (json& u : doc["server"]["users"])
    if (u.value("name", "") == name) return &u;
  return nullptr;
}

}  // namespace

HttpReply RestApi::route_users(const HttpRequest& req, const std::string& path, const SessionInfo& session) {
  const http::verb m = req.method();
  if (path == "/api/users") {
    if (m != http::verb::post) return method_not_allowed("GET, POST");
    const HttpReply reply = add_user(req, session);
    const json body = json::parse(req.body(), nullptr, false);
    audit(session, "user_add", body.is_object() && body.contains("name") && body["name"].is_string() ? body["name"].get<std::string>() : "", reply);
    return reply;
  }
  if (path.rfind("/api/users/", 0) == 0) {
    const std::string name = path.substr(11);
    if (m != http::verb::put && m != http::verb::delete_) return method_not_allowed("PUT, DELETE");
    const HttpReply reply = m == http::verb::put ? change_user(req, name, session) : remove_user(name, session);
    audit(session, m == http::verb::put ? "user_change" : "user_remove", name, reply);
    return reply;
  }
  // /api/sessions/{id}
  const std::string id = path.substr(14);
  if (m != http::verb::delete_) return method_not_allowed("DELETE");
  const HttpReply reply = [&] {
    if (!sessions_.end(id)) return HttpReply::error(http::status::not_found, "no session '" + id + "'");
    const std::size_t closed = lab_.disconnect_where([&](const SessionInfo& s) { return s.id == id; }, "session ended by " + session.user);
    return ok_json({{"ended", id}, {"connections_closed", closed}});
  }();
  audit(session, "session_end", id, reply);
  return reply;
}

HttpReply RestApi::add_user(const HttpRequest& req, const SessionInfo&) {
  auto parsed = json_object_body(req, {"name", "role", "password"});
  if (auto* refused = std::get_if<HttpReply>(&parsed)) return *refused;
  const json& body = std::get<json>(parsed);
  if (!body.contains("name") || !body["name"].is_string() || !body.contains("role") || !body.contains("password"))
    return bad_request("a new user needs 'name', 'role' and 'password' (strings)");
  if (auto refused = check_fields(body)) return *refused;
  const std::string name = body["name"];
  if (!valid_user_name(name))
    return HttpReply::error(http::status::unprocessable_entity, "'name' must be 1 to 64 letters, digits, '_', '-' or '.'");
  return edit_users([&](json& doc) -> std::optional<HttpReply> {
    if (find_user(doc, name)) return HttpReply::error(http::status::conflict, "user '" + name + "' exists");
    doc["server"]["users"].push_back({{"name", name}, {"role", body["role"]},
                                      {"password_hash", PasswordHash::create(body["password"].get<std::string>()).encode()}});
    return std::nullopt;
  }, http::status::created, {{"added", name}, {"role", body["role"]}});
}

HttpReply RestApi::change_user(const HttpRequest& req, const std::string& name, const SessionInfo& session) {
  auto parsed = json_object_body(req, {"role", "password"});
  if (auto* refused = std::get_if<HttpReply>(&parsed)) return *refused;
  const json& body = std::get<json>(parsed);
  if (body.empty()) return bad_request("send 'role', 'password' or both");
  if (auto refused = check_fields(body)) return *refused;
  // An admin who demoted themselves might leave the lab without one.
  if (name == session.user && body.contains("role") && body["role"] != to_string(session.role))
    return HttpReply::error(http::status::conflict, "you may not change your own role");
  return edit_users([&](json& doc) -> std::optional<HttpReply> {
    json* user = find_user(doc, name);
    if (!user) return HttpReply::error(http::status::not_found, "no user '" + name + "'");
    if (body.contains("role")) (*user)["role"] = body["role"];
    if (body.contains("password")) (*user)["password_hash"] = PasswordHash::create(body["password"].get<std::string>()).encode();
    return std::nullopt;
  }, http::status::ok, {{"changed", name}});
}

HttpReply RestApi::remove_user(const std::string& name, const SessionInfo& session) {
  if (name == session.user) return HttpReply::error(http::status::conflict, "you may not remove yourself");
  return edit_users([&](json& doc) -> std::optional<HttpReply> {
    json& users = doc["server"]["users"];
    for (auto it = users.begin(); it != users.end(); ++it)
      if (it->value("name", "") == name) {
        users.erase(it);
        return std::nullopt;
      }
    return HttpReply::error(http::status::not_found, "no user '" + name + "'");
  }, http::status::ok, {{"removed", name}});
}

HttpReply RestApi::edit_users(const std::function<std::optional<HttpReply>(json&)>& edit, http::status status, json answer) {
  std::lock_guard lock(config_mutex_);  // two admins' edits must not lose one another
  auto read = read_config_json(config_file_);
  if (auto* err = std::get_if<ConfigFileError>(&read)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
  json& doc = std::get<json>(read);
  if (!doc.contains("server") || !doc["server"].is_object()) doc["server"] = json::object();
  if (!doc["server"].contains("users") || !doc["server"]["users"].is_array()) doc["server"]["users"] = json::array();
  if (auto refused = edit(doc)) return *refused;
  auto written = replace_config(config_file_, doc);
  if (auto* err = std::get_if<ConfigFileError>(&written)) return HttpReply::error(static_cast<http::status>(err->status), err->message);
  apply_users(std::get<AppConfig>(written).server.users);
  answer["saved"] = config_file_.filename().string();
  return ok_json(answer, status);
}

void RestApi::apply_users(const std::vector<UserAccount>& users) {
  for (const std::string& ended : sessions_.set_users(users))
    lab_.disconnect_where([&](const SessionInfo& s) { return s.user == ended; }, "user " + ended + " removed or given another role");
}

}  // namespace labo::server
