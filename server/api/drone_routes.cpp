#include "server/api/drone_routes.hpp"

#include <nlohmann/json.hpp>

#include "server/auth/permissions.hpp"

namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

std::optional<HttpReply> drone_route(const HttpRequest& req, const std::string& path, Role role, FlightService& flight) {
  if (path != "/api/drone/set-down") return std::nullopt;
  if (req.method() != http::verb::post) {
    HttpReply r = HttpReply::error(http::status::method_not_allowed, "method not allowed here; allowed: POST");
    r.headers.emplace_back("Allow", "POST");
    return r;
  }
  if (!role_may(role, Permission::Administer))
    return HttpReply::error(http::status::forbidden, "role " + to_string(role) + " may not say where the drone is");
  if (!req.body().empty()) {
    const json j = json::parse(req.body(), nullptr, false);
    if (j.is_discarded()) return HttpReply::error(http::status::bad_request, "malformed JSON");
    if (!j.is_object() || !j.empty())
      return HttpReply::error(http::status::bad_request, "expected no body or {} (the platform is the lab file's base)");
  }
  const CommandVerdict verdict = flight.set_down_on_platform();
  if (!verdict.accepted) return HttpReply::error(http::status::conflict, verdict.reason);
  return HttpReply::json(http::status::ok, json{{"accepted", true}, {"reason", verdict.reason}}.dump());
}

}  // namespace labo::server
