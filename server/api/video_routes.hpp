#pragma once
// The drone's video through REST: GET /api/video (anyone logged in: its cameras, the bit rate the
// link asks of the drone and its range, the low rendition's rate) and PUT /api/video/bitrate
// {"kbps": N} (admin: the link asks the drone for N kbit/s from now on and at every reconnection;
// refused with 409 by a drone whose link has no such setting). Validated like every route: wrong
// method 405, body that is not {"kbps": integer} 400, a rate outside the drone's range 400.
#include <optional>
#include <string>

#include "server/api/http_reply.hpp"
#include "server/api/rest_api.hpp"

namespace labo::server {

// The reply when `path` is one of the video routes, nullopt otherwise.
std::optional<HttpReply> video_route(const HttpRequest& req, const std::string& path, Role role, FlightService& flight,
                                     int low_rendition_kbps);

// The bit rate a PUT /api/video/bitrate body asks for, as its text ("2000"), or "" when the body
// names none: the audit log's target, for refused requests too.
std::string requested_kbps(const HttpRequest& req);

}  // namespace labo::server
