#include "control/flight_types.hpp"

#include "localization/fusion/lab_geometry.hpp"

namespace labo::control {

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
    case RequestKind::SelectCamera: return "select_camera";
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

}  // namespace labo::control
