#include "drone/ardrone2/video_bitrate.hpp"

#include <cstdlib>
#include <optional>

namespace labo::ardrone2 {

namespace {

std::optional<int> parse_int(const std::string& text, int min, int max) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || !end || *end != '\0' || v < min || v > max) return std::nullopt;
  return static_cast<int>(v);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> video_bitrate_configs(int kbps) {
  const std::string rate = std::to_string(kbps);
  return {{"video:bitrate_ctrl_mode", std::to_string(static_cast<int>(VideoBitrateMode::FixedToMax))},
          {"video:max_bitrate", rate},
          {"video:bitrate", rate}};
}

bool VideoBitrateControl::is_key(const std::string& key) {
  return key == "video:bitrate_ctrl_mode" || key == "video:max_bitrate" || key == "video:bitrate";
}

bool VideoBitrateControl::apply(const std::string& key, const std::string& value) {
  if (key == "video:bitrate_ctrl_mode") {
    const auto v = parse_int(value, 0, 2);
    if (v) mode_ = static_cast<VideoBitrateMode>(*v);
    return v.has_value();
  }
  const auto v = parse_int(value, kMinVideoBitrateKbps, kMaxVideoBitrateKbps);
  if (!v) return false;
  if (key == "video:max_bitrate") {
    max_kbps_ = *v;
  } else if (key == "video:bitrate") {
    manual_kbps_ = *v;
  } else {
    return false;
  }
  return true;
}

}  // namespace labo::ardrone2
