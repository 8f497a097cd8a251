#pragma once
// The WebSocket's Origin check. A browser sends the Origin of the page that opens a WebSocket, and
// sends the lab's session cookie with it whatever that page is: without this check any page the
// user visits could fly the drone on their session (cross-site WebSocket hijacking). Pure.
#include <string>
#include <string_view>

namespace labo::server {

// Empty when the upgrade may proceed, otherwise why not. `origin` is the request's Origin header
// (empty when absent: scripts and non-browser clients send none, and carry their token themselves);
// `host` its Host header; `configured` the server's `origin` setting (scheme://host[:port]), empty
// to accept only an origin naming the host the request names.
std::string origin_refusal(std::string_view origin, std::string_view host, std::string_view configured);

}  // namespace labo::server
