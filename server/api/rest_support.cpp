#include "server/api/rest_support.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace labo::server {

namespace http = boost::beast::http;
using nlohmann::json;

HttpReply ok_json(const json& j, http::status status) { return HttpReply::json(status, j.dump()); }

HttpReply method_not_allowed(const std::string& allowed) {
  HttpReply r = HttpReply::error(http::status::method_not_allowed, "method not allowed here; allowed: " + allowed);
  r.headers.emplace_back("Allow", allowed);
  return r;
}

HttpReply bad_request(const std::string& message) { return HttpReply::error(http::status::bad_request, message); }

std::optional<std::string> query_value(std::string_view target, std::string_view name) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return std::nullopt;
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == name) return std::string(eq == std::string_view::npos ? std::string_view{} : pair.substr(eq + 1));
    if (amp == std::string_view::npos) break;
    rest.remove_prefix(amp + 1);
  }
  return std::nullopt;
}

std::variant<long, HttpReply> query_integer(std::string_view target, std::string_view name, long fallback, long min, long max) {
  const auto text = query_value(target, name);
  if (!text) return fallback;
  long value = 0;
  const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec != std::errc{} || end != text->data() + text->size() || value < min || value > max)
    return bad_request("query parameter '" + std::string(name) + "' must be an integer in [" + std::to_string(min) + ", " +
                       std::to_string(max) + "], got '" + *text + "'");
  return value;
}

bool safe_file_name(const std::string& name) {
  if (name.empty() || name.size() > 128 || name[0] == '.') return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) return false;
  return true;
}

std::variant<json, HttpReply> json_object_body(const HttpRequest& req, std::initializer_list<std::string_view> allowed) {
  const json j = json::parse(req.body(), nullptr, false);
  if (j.is_discarded()) return bad_request("malformed JSON");
  if (!j.is_object()) return bad_request("expected a JSON object");
  for (const auto& [key, value] : j.items())
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string names;
      for (std::string_view a : allowed) names += (names.empty() ? "" : ", ") + std::string(a);
      return bad_request("unknown field '" + key + "' (expected " + names + ")");
    }
  return j;
}

}  // namespace labo::server
