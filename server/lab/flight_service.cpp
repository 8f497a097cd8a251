#include "server/lab/flight_service.hpp"

#include <array>
#include <utility>

#include "localization/fusion/localization_pipelines.hpp"

namespace labo::server {

namespace {
constexpr std::array<std::pair<MissionCommandKind, const char*>, 10> kCommands{{
    {MissionCommandKind::Takeoff, "takeoff"},
    {MissionCommandKind::Inspect, "inspect"},
    {MissionCommandKind::FindTeacher, "find_teacher"},
    {MissionCommandKind::StopFaceFollow, "stop_face_follow"},
    {MissionCommandKind::ReturnHome, "return_home"},
    {MissionCommandKind::Land, "land"},
    {MissionCommandKind::Stop, "stop"},
    {MissionCommandKind::EmergencyStop, "emergency_stop"},
    {MissionCommandKind::SelectCamera, "select_camera"},
    {MissionCommandKind::Jog, "jog"},
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

// The flight software's palette (fusion::colour_of: the paper's green, blue and red, the face
// orange), and the paper's black when the object's tracking failed.
std::string colour_of(PoseSource source) {
  switch (source) {
    case PoseSource::Slam: return fusion::colour_of(fusion::FeedbackSource::Slam);
    case PoseSource::Homography: return fusion::colour_of(fusion::FeedbackSource::Homography);
    case PoseSource::Face: return fusion::colour_of(fusion::FeedbackSource::Face);
    case PoseSource::DeadReckoning: return fusion::colour_of(fusion::FeedbackSource::DeadReckoning);
    case PoseSource::VisionLost: return "#000000";
  }
  return "#e00000";
}

}  // namespace labo::server
