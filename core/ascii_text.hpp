#pragma once
// ASCII case folding for protocol text (HTTP header names and values, media types): locale-free, so
// a server's locale never changes what a request means.
#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

namespace labo {

inline std::string ascii_lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace labo
