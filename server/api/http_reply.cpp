#include "server/api/http_reply.hpp"

#include <nlohmann/json.hpp>

namespace labo::server {

HttpReply HttpReply::json(boost::beast::http::status status, std::string body) {
  HttpReply r;
  r.status = status;
  r.body = std::move(body);
  return r;
}

HttpReply HttpReply::error(boost::beast::http::status status, const std::string& message) {
  return json(status, nlohmann::json{{"status", static_cast<int>(status)}, {"error", message}}.dump());
}

std::string content_type_for(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".ico") return "image/x-icon";
  return "application/octet-stream";
}

}  // namespace labo::server
