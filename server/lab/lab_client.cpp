#include "server/lab/lab_client.hpp"

namespace labo::server {

std::string_view to_string(VideoPath path) {
  switch (path) {
    case VideoPath::H264: return "h264";
    case VideoPath::Geometry: return "geometry";
    case VideoPath::None: return "none";
    case VideoPath::Jpeg: break;
  }
  return "jpeg";
}

std::optional<VideoPath> parse_video_path(std::string_view text) {
  if (text == "h264") return VideoPath::H264;
  if (text == "jpeg") return VideoPath::Jpeg;
  if (text == "geometry") return VideoPath::Geometry;
  if (text == "none") return VideoPath::None;
  return std::nullopt;
}

}  // namespace labo::server
