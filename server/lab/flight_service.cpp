#include "server/lab/flight_service.hpp"

#include <array>
#include <utility>

namespace labo {

namespace {
constexpr std::array<std::pair<MissionCommandKind, const char*>, 7> kCommands{{
    {MissionCommandKind::Takeoff, "takeoff"},
    {MissionCommandKind::Inspect, "inspect"},
    {MissionCommandKind::FindTeacher, "find_teacher"},
    {MissionCommandKind::StopFaceFollow, "stop_face_follow"},
    {MissionCommandKind::ReturnHome, "return_home"},
    {MissionCommandKind::Land, "land"},
    {MissionCommandKind::EmergencyStop, "emergency_stop"},
}};
}  // namespace

std::string to_string(MissionCommandKind kind) {
  for (const auto& [k, name] : kCommands)
    if (k == kind) return name;
  return "unknown";
}

std::optional<MissionCommandKind> parse_mission_command(const std::string& text) {
  for (const auto& [k, name] : kCommands)
    if (text == name) return k;
  return std::nullopt;
}

std::string to_string(PoseSource source) {
  switch (source) {
    case PoseSource::Slam: return "slam";
    case PoseSource::Homography: return "homography";
    case PoseSource::Face: return "face";
    case PoseSource::DeadReckoning: return "dead_reckoning";
    case PoseSource::VisionLost: return "vision_lost";
  }
  return "dead_reckoning";
}

// The paper: green while SLAM tracks, red on navdata alone after SLAM loss, blue from the panel's
// homography, black when the object tracking fails. Face (not coloured in the paper): orange.
std::string colour_of(PoseSource source) {
  switch (source) {
    case PoseSource::Slam: return "#00b000";
    case PoseSource::Homography: return "#1060ff";
    case PoseSource::Face: return "#ff9000";
    case PoseSource::DeadReckoning: return "#e00000";
    case PoseSource::VisionLost: return "#000000";
  }
  return "#e00000";
}

}  // namespace labo
