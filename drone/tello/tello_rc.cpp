#include "drone/tello/tello_rc.hpp"

#include <array>
#include <charconv>
#include <cstdio>
#include <cstdlib>

namespace labo::tello {

namespace {
bool parse_stick(std::string_view text, int& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && ec == std::errc() && end == text.data() + text.size() && std::abs(value) <= kMaxStick;
}
}  // namespace

void format_rc(const RcSticks& s, std::string& out) {
  char buf[48];
  const int n = std::snprintf(buf, sizeof(buf), "rc %d %d %d %d", s.a, s.b, s.c, s.d);
  out.assign(buf, static_cast<std::size_t>(n));
}

bool parse_rc_arguments(std::string_view text, RcSticks& sticks) {
  std::array<int*, 4> values = {&sticks.a, &sticks.b, &sticks.c, &sticks.d};
  for (std::size_t i = 0; i < values.size(); ++i) {
    while (text.starts_with(' ')) text.remove_prefix(1);
    const std::size_t space = text.find(' ');
    if (!parse_stick(text.substr(0, space), *values[i])) return false;
    text = space == std::string_view::npos ? std::string_view() : text.substr(space);
  }
  while (text.starts_with(' ')) text.remove_prefix(1);
  return text.empty();
}

}  // namespace labo::tello
