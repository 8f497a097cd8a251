#pragma once
// Small pieces every REST route file shares: JSON answers, 405 with Allow, query parameters, the
// JSON-object body check.
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "server/api/http_reply.hpp"

namespace labo::server {

using HttpRequest = boost::beast::http::request<boost::beast::http::string_body>;

HttpReply ok_json(const nlohmann::json& j, boost::beast::http::status status = boost::beast::http::status::ok);
HttpReply method_not_allowed(const std::string& allowed);
HttpReply bad_request(const std::string& message);
// The value of `name` in the request target's query string, if present (not URL-decoded: the
// parameters read this way are numbers).
std::optional<std::string> query_value(std::string_view target, std::string_view name);
// A non-negative integer query parameter within [min, max], `fallback` when absent; a refusal
// naming the parameter otherwise.
std::variant<long, HttpReply> query_integer(std::string_view target, std::string_view name, long fallback, long min, long max);
// A file name the server may serve from one of its folders: letters, digits, '.', '_', '-', not
// starting with '.', at most 128 characters.
bool safe_file_name(const std::string& name);
// The body as a JSON object whose keys are all in `allowed`; a 400 naming what was wrong otherwise.
std::variant<nlohmann::json, HttpReply> json_object_body(const HttpRequest& req, std::initializer_list<std::string_view> allowed);

}  // namespace labo::server
