#include "drone/tello/tello_camera_switch.hpp"

namespace labo::tello {

TelloCameraSwitch::Decision TelloCameraSwitch::select(CameraId camera) {
  if (camera == wanted_) return {};
  if (camera == CameraId::Bottom && !available_) return {.command = std::nullopt, .unavailable = true};
  wanted_ = camera;
  return {.command = camera == CameraId::Bottom ? kDownvisionOn : kDownvisionOff, .unavailable = false};
}

bool TelloCameraSwitch::finished(const CommandOutcome& o) {
  if (o.command != kDownvisionOn) return false;
  using Result = CommandOutcome::Result;
  if (o.result == Result::Ok || o.result == Result::Abandoned) return false;  // abandoned: an emergency, not a refusal
  const bool first = available_;
  available_ = false;
  wanted_ = CameraId::Front;
  return first;
}

std::optional<std::string_view> TelloCameraSwitch::after_sdk_mode() const {
  if (wanted_ == CameraId::Bottom && available_) return kDownvisionOn;
  return std::nullopt;
}

}  // namespace labo::tello
