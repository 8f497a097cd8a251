#pragma once
// What an admin tells LaboDrone about the drone itself: POST /api/drone/set-down (admin, no body or
// {}): someone set the drone on its charging platform, so its place is the base's again. A drone
// landed after a silence in flight, with no fix on the lab since, takes no mission until then
// (control/request_policy.cpp). Refused with 409 while the drone flies or a mission runs, 403 for
// another role, 405 for another method, 400 for a body that is not empty or {}.
#include <optional>
#include <string>

#include "server/api/http_reply.hpp"
#include "server/api/rest_api.hpp"

namespace labo::server {

// The reply when `path` is one of the drone routes, nullopt otherwise.
std::optional<HttpReply> drone_route(const HttpRequest& req, const std::string& path, Role role, FlightService& flight);

}  // namespace labo::server
