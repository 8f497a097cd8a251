#include "server/lab/lab_client.hpp"

namespace labo {

std::string_view to_string(VideoPath path) { return path == VideoPath::H264 ? "h264" : "jpeg"; }

std::optional<VideoPath> parse_video_path(std::string_view text) {
  if (text == "h264") return VideoPath::H264;
  if (text == "jpeg") return VideoPath::Jpeg;
  return std::nullopt;
}

}  // namespace labo
