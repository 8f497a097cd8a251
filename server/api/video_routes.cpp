#include "server/api/video_routes.hpp"

#include <nlohmann/json.hpp>

#include "server/auth/permissions.hpp"

namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

namespace {

HttpReply wrong_method(const std::string& allowed) {
  HttpReply r = HttpReply::error(http::status::method_not_allowed, "method not allowed here; allowed: " + allowed);
  r.headers.emplace_back("Allow", allowed);
  return r;
}

json video_json(const VideoCapabilities& v, int low_rendition_kbps) {
  return {{"drone", v.drone},
          {"bottom_camera", v.bottom_camera},
          {"no_bottom_camera", v.no_bottom_camera},
          {"adjustable_bitrate", v.adjustable_bitrate},
          {"bitrate_kbps", v.bitrate_kbps},
          {"min_bitrate_kbps", v.min_bitrate_kbps},
          {"max_bitrate_kbps", v.max_bitrate_kbps},
          {"low_rendition_kbps", low_rendition_kbps}};
}

HttpReply put_bitrate(const HttpRequest& req, FlightService& flight, int low_rendition_kbps) {
  const json j = json::parse(req.body(), nullptr, false);
  if (j.is_discarded()) return HttpReply::error(http::status::bad_request, "malformed JSON");
  if (!j.is_object()) return HttpReply::error(http::status::bad_request, "expected a JSON object {\"kbps\": integer}");
  for (const auto& [key, value] : j.items())
    if (key != "kbps") return HttpReply::error(http::status::bad_request, "unknown field '" + key + "' (expected 'kbps')");
  if (!j.contains("kbps") || !j["kbps"].is_number_integer())
    return HttpReply::error(http::status::bad_request, "'kbps' (integer, kbit/s) is required");
  const VideoCapabilities v = flight.video_capabilities();
  if (!v.adjustable_bitrate)
    return HttpReply::error(http::status::conflict, (v.drone.empty() ? std::string("this drone") : v.drone) +
                                                        ": the link cannot ask the drone for a video bit rate");
  const auto kbps = j["kbps"].get<std::int64_t>();
  if (kbps < v.min_bitrate_kbps || kbps > v.max_bitrate_kbps)
    return HttpReply::error(http::status::bad_request, "'kbps' must be in [" + std::to_string(v.min_bitrate_kbps) + ", " +
                                                           std::to_string(v.max_bitrate_kbps) + "] for " + v.drone +
                                                           ", got " + std::to_string(kbps));
  const CommandVerdict verdict = flight.set_video_bitrate(static_cast<int>(kbps));
  if (!verdict.accepted) return HttpReply::error(http::status::conflict, verdict.reason);
  return HttpReply::json(http::status::ok, video_json(flight.video_capabilities(), low_rendition_kbps).dump());
}

}  // namespace

std::optional<HttpReply> video_route(const HttpRequest& req, const std::string& path, Role role, FlightService& flight,
                                     int low_rendition_kbps) {
  if (path == "/api/video") {
    if (req.method() != http::verb::get) return wrong_method("GET");
    return HttpReply::json(http::status::ok, video_json(flight.video_capabilities(), low_rendition_kbps).dump());
  }
  if (path == "/api/video/bitrate") {
    if (req.method() != http::verb::put) return wrong_method("PUT");
    if (!role_may(role, Permission::Administer))
      return HttpReply::error(http::status::forbidden, "role " + to_string(role) + " may not set the video bit rate");
    return put_bitrate(req, flight, low_rendition_kbps);
  }
  return std::nullopt;
}

std::string requested_kbps(const HttpRequest& req) {
  const json j = json::parse(req.body(), nullptr, false);
  if (!j.is_object() || !j.contains("kbps") || !j["kbps"].is_number()) return "";
  return j["kbps"].dump();
}

}  // namespace labo::server
