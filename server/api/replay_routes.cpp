#include <nlohmann/json.hpp>
#include <variant>

#include "server/api/rest_api.hpp"

// Recordings played back in the page (ReplayService): start, status, stop. Admin only (route_admin).
namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

HttpReply outcome_reply(const ReplayOutcome& o, const std::optional<ReplayStatus>& status) {
  if (o.status != 200) return HttpReply::error(static_cast<http::status>(o.status), o.message);
  return ok_json({{"message", o.message},
                  {"replay", status ? json::parse(replay_status_json(*status, false)) : json(nullptr)}});
}

}  // namespace

HttpReply RestApi::start_replay(const HttpRequest& req, const std::string& name, const SessionInfo& session) {
  if (!safe_file_name(name)) return HttpReply::error(http::status::bad_request, "invalid recording name '" + name + "'");
  json body = json::object();
  if (!req.body().empty()) {
    auto parsed = json_object_body(req, {"audience", "speed"});
    if (auto* refused = std::get_if<HttpReply>(&parsed)) return *refused;
    body = std::get<json>(parsed);
  }
  ReplayAudience audience = ReplayAudience::Requester;
  if (body.contains("audience")) {
    const json& a = body["audience"];
    const auto parsed = a.is_string() ? parse_replay_audience(a.get<std::string>()) : std::nullopt;
    if (!parsed) return bad_request("audience must be \"me\" or \"everyone\"");
    audience = *parsed;
  }
  double speed = 1.0;
  if (body.contains("speed")) {
    const json& s = body["speed"];
    if (!s.is_number() || !(s.get<double>() >= ReplayService::kMinSpeed && s.get<double>() <= ReplayService::kMaxSpeed))
      return HttpReply::error(http::status::unprocessable_entity, "speed must be a number from 0.25 to 8");
    speed = s.get<double>();
  }
  const auto file = settings_.recordings_dir / name;
  if (!std::filesystem::is_regular_file(file)) return HttpReply::error(http::status::not_found, "no recording '" + name + "'");
  ReplayService& replays = lab_.replays();
  const ReplayOutcome o = replays.start(session.user, name, file, audience, speed);
  return outcome_reply(o, replays.status());
}

HttpReply RestApi::route_replay(const HttpRequest& req, const SessionInfo& session) {
  ReplayService& replays = lab_.replays();
  if (req.method() == http::verb::get) {
    const auto s = replays.status();
    return ok_json({{"replay", s ? json::parse(replay_status_json(*s, false)) : json(nullptr)}});
  }
  if (req.method() != http::verb::delete_) return method_not_allowed("GET, DELETE");
  const HttpReply reply = outcome_reply(replays.stop(session.user), replays.status());
  const auto s = replays.status();
  audit(session, "replay_stop", s ? s->name : "", reply);
  return reply;
}

}  // namespace labo::server
