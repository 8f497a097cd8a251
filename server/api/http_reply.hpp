#pragma once
// A response as the REST router builds it, independent of the socket: a status, a body (or a file to
// stream) and headers. The HTTP session turns it into a Beast message.
#include <boost/beast/http/status.hpp>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace labo::server {

struct HttpReply {
  boost::beast::http::status status = boost::beast::http::status::ok;
  std::string content_type = "application/json";
  std::string body;
  std::optional<std::filesystem::path> file;  // streamed instead of body
  std::vector<std::pair<std::string, std::string>> headers;
  // Set: the answer is work the connection's I/O thread must not do (a face registration). The
  // session calls `deferred` with a function that takes the final reply, callable once from any
  // thread; everything else in this reply is ignored.
  std::function<void(std::function<void(HttpReply)>)> deferred;

  static HttpReply json(boost::beast::http::status status, std::string body);
  // {"status": <code>, "error": <message>}
  static HttpReply error(boost::beast::http::status status, const std::string& message);
};

// Content type from a file extension (".html" -> "text/html; charset=utf-8").
std::string content_type_for(const std::filesystem::path& file);

}  // namespace labo::server
