#include "server/api/multipart_form.hpp"

#include <optional>

#include "core/ascii_text.hpp"

namespace labo::server {

namespace {

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

// The value of parameter `key` in "type; a=1; b="two"" (quotes removed), if present.
std::optional<std::string> header_parameter(std::string_view header, std::string_view key) {
  std::size_t pos = header.find(';');
  while (pos != std::string_view::npos) {
    std::string_view rest = header.substr(pos + 1);
    const std::size_t end = rest.find(';');
    std::string_view item = trim(rest.substr(0, end));
    const std::size_t eq = item.find('=');
    if (eq != std::string_view::npos && ascii_lower(trim(item.substr(0, eq))) == key) {
      std::string_view value = trim(item.substr(eq + 1));
      if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
      return std::string(value);
    }
    pos = end == std::string_view::npos ? end : pos + 1 + end;
  }
  return std::nullopt;
}

// One part's headers (the text before its blank line) into `part`; an error text otherwise.
std::string read_part_headers(std::string_view headers, FormPart& part) {
  bool disposition = false;
  while (!headers.empty()) {
    const std::size_t eol = headers.find("\r\n");
    const std::string_view line = headers.substr(0, eol);
    headers = eol == std::string_view::npos ? std::string_view{} : headers.substr(eol + 2);
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) return "a part's header line has no ':'";
    const std::string name = ascii_lower(trim(line.substr(0, colon)));
    const std::string_view value = trim(line.substr(colon + 1));
    if (name == "content-disposition") {
      if (ascii_lower(value.substr(0, value.find(';'))) != "form-data") return "a part's Content-Disposition is not form-data";
      const auto field = header_parameter(value, "name");
      if (!field || field->empty()) return "a part has no field name";
      part.name = *field;
      part.filename = header_parameter(value, "filename").value_or("");
      disposition = true;
    } else if (name == "content-type") {
      part.content_type = ascii_lower(trim(value.substr(0, value.find(';'))));
    }
  }
  return disposition ? std::string() : "a part has no Content-Disposition";
}

}  // namespace

bool is_multipart_form(std::string_view content_type) {
  return ascii_lower(trim(content_type.substr(0, content_type.find(';')))) == "multipart/form-data";
}

std::variant<std::vector<FormPart>, std::string> parse_multipart_form(std::string_view content_type, std::string_view body,
                                                                      std::size_t max_parts) {
  if (!is_multipart_form(content_type)) return std::string("expected a multipart/form-data body");
  const auto boundary = header_parameter(content_type, "boundary");
  if (!boundary || boundary->empty() || boundary->size() > 70) return std::string("multipart/form-data without a boundary of 1-70 characters");
  const std::string delimiter = "--" + *boundary;
  std::size_t pos = body.find(delimiter);
  if (pos == std::string_view::npos) return std::string("the body holds no part (no boundary line)");
  std::vector<FormPart> parts;
  const std::string next_delimiter = "\r\n" + delimiter;
  while (true) {
    pos += delimiter.size();
    if (body.substr(pos, 2) == "--") return parts;  // the closing delimiter
    if (body.substr(pos, 2) != "\r\n") return std::string("a boundary line does not end with CRLF");
    pos += 2;
    const std::size_t headers_end = body.find("\r\n\r\n", pos);
    if (headers_end == std::string_view::npos) return std::string("a part's headers do not end");
    if (parts.size() == max_parts) return "more than " + std::to_string(max_parts) + " parts";
    FormPart part;
    if (std::string error = read_part_headers(body.substr(pos, headers_end - pos), part); !error.empty()) return error;
    const std::size_t data = headers_end + 4;
    const std::size_t end = body.find(next_delimiter, data);
    if (end == std::string_view::npos) return "part '" + part.name + "' does not end (no closing boundary)";
    part.body = body.substr(data, end - data);
    parts.push_back(std::move(part));
    pos = end + 2;
  }
}

}  // namespace labo::server
