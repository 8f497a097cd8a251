#pragma once
// A multipart/form-data body (RFC 7578), as a browser's FormData or `curl -F` sends it: its parts'
// field names, file names, declared types and bytes. The parts view the body, which must outlive
// them. Malformed input is refused with what was wrong; nothing is decoded or written here.
#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace labo::server {

struct FormPart {
  std::string name;          // Content-Disposition's name
  std::string filename;      // its filename, empty for a plain field
  std::string content_type;  // the part's Content-Type, lower case, without parameters ("" when absent)
  std::string_view body;
};

// `content_type` is the request's header ("multipart/form-data; boundary=..."). The error names what
// was wrong: no boundary, a part without a name, more than `max_parts` parts, a missing end.
std::variant<std::vector<FormPart>, std::string> parse_multipart_form(std::string_view content_type, std::string_view body,
                                                                      std::size_t max_parts);

// Whether `content_type` (a request's header) is multipart/form-data.
bool is_multipart_form(std::string_view content_type);

}  // namespace labo::server
