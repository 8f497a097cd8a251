#include "control/flight_types.hpp"

#include "localization/fusion/lab_geometry.hpp"

namespace labo {

std::string to_string(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "slam";
    case FeedbackSource::Homography: return "homography";
    case FeedbackSource::Face: return "face";
    case FeedbackSource::DeadReckoning: return "dead_reckoning";
  }
  return "unknown";
}

// The paper's colour code: green SLAM, blue homography, red/black dead reckoning; face in purple.
std::string colour_of(FeedbackSource source) {
  switch (source) {
    case FeedbackSource::Slam: return "#1a9850";
    case FeedbackSource::Homography: return "#2166ac";
    case FeedbackSource::Face: return "#984ea3";
    case FeedbackSource::DeadReckoning: return "#d73027";
  }
  return "#000000";
}

std::string to_string(TrackState state) {
  switch (state) {
    case TrackState::Off: return "off";
    case TrackState::Searching: return "searching";
    case TrackState::Tracking: return "tracking";
    case TrackState::Lost: return "lost";
  }
  return "unknown";
}

std::string to_string(SlamState state) {
  switch (state) {
    case SlamState::Off: return "off";
    case SlamState::Initializing: return "initializing";
    case SlamState::Good: return "good";
    case SlamState::Dodgy: return "dodgy";
    case SlamState::Lost: return "lost";
  }
  return "unknown";
}

std::string to_string(RequestKind kind) {
  switch (kind) {
    case RequestKind::Takeoff: return "takeoff";
    case RequestKind::Land: return "land";
    case RequestKind::Hover: return "hover";
    case RequestKind::Goto: return "goto";
    case RequestKind::MoveBy: return "move_by";
    case RequestKind::Inspect: return "inspect";
    case RequestKind::FindTeacher: return "find_teacher";
    case RequestKind::StopFaceFollow: return "stop_face_follow";
    case RequestKind::ReturnHome: return "return_home";
    case RequestKind::EmergencyStop: return "emergency_stop";
  }
  return "unknown";
}

std::string to_string(FlightOutput::Action action) {
  switch (action) {
    case FlightOutput::Action::None: return "none";
    case FlightOutput::Action::Move: return "move";
    case FlightOutput::Action::Hover: return "hover";
    case FlightOutput::Action::Takeoff: return "takeoff";
    case FlightOutput::Action::Land: return "land";
    case FlightOutput::Action::Emergency: return "emergency";
  }
  return "unknown";
}

std::string to_string(FlightPhase phase) {
  switch (phase) {
    case FlightPhase::Landed: return "landed";
    case FlightPhase::TakingOff: return "taking_off";
    case FlightPhase::Flying: return "flying";
    case FlightPhase::Landing: return "landing";
    case FlightPhase::Emergency: return "emergency";
  }
  return "unknown";
}

}  // namespace labo
