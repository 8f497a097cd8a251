#include "server/http/origin_check.hpp"

#include "core/ascii_text.hpp"

namespace labo::server {

namespace {

std::string_view without_trailing_slashes(std::string_view text) {
  while (!text.empty() && text.back() == '/') text.remove_suffix(1);
  return text;
}

}  // namespace

std::string origin_refusal(std::string_view origin, std::string_view host, std::string_view configured) {
  if (origin.empty()) return {};
  const std::string o = ascii_lower(without_trailing_slashes(origin));
  if (!configured.empty()) {
    if (o == ascii_lower(without_trailing_slashes(configured))) return {};
    return "WebSocket from origin '" + std::string(origin) + "' refused: this server accepts pages of " + std::string(configured);
  }
  const auto scheme_end = o.find("://");
  const bool web_scheme = o.rfind("http://", 0) == 0 || o.rfind("https://", 0) == 0;
  if (!web_scheme || scheme_end == std::string::npos || o.substr(scheme_end + 3) != ascii_lower(host))
    return "WebSocket from origin '" + std::string(origin) + "' refused: only pages served by " + std::string(host) + " may open it";
  return {};
}

}  // namespace labo::server
