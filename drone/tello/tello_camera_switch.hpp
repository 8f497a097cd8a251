#pragma once
// The driver's side of the Tello EDU's downward camera (docs/tello.md "The downward camera"):
// "downvision 1" switches the video stream to the downward camera, "downvision 0" back to the front
// one, each answered "ok" or "error" like any setting. A plain Tello has no such command: it answers
// "error" (or nothing); from then on the bottom camera is unavailable and the flight software's
// request is refused in the open (the link counts and logs it, frames stay front), never faked.
//
// TelloCameraSwitch decides, without any I/O, which command a camera request sends and learns from
// the command's outcome whether the drone has the camera. TelloLink and SimTelloLink share it.
// Which camera a frame came from is told by the frame's size (TelloVideoReceiver): the downward
// camera streams kDownvisionWidth x kDownvisionHeight pictures.
#include <optional>
#include <string_view>

#include "drone/drone_link.hpp"
#include "drone/tello/tello_command.hpp"

namespace labo::tello {

// The downward camera's pictures: 320x240, grey (docs/tello.md "The downward camera").
inline constexpr int kDownvisionWidth = 320, kDownvisionHeight = 240;
inline constexpr std::string_view kDownvisionOn = "downvision 1";
inline constexpr std::string_view kDownvisionOff = "downvision 0";

class TelloCameraSwitch {
 public:
  // `ask_drone`: the configuration says the drone may have the downward camera (tello.link.downvision).
  explicit TelloCameraSwitch(bool ask_drone) : available_(ask_drone) {}

  struct Decision {
    std::optional<std::string_view> command;  // to queue, if any
    bool unavailable = false;                 // the bottom camera was asked for and cannot be had
  };
  Decision select(CameraId camera);
  // A command ended. True when it was a "downvision 1" the drone refused or left unanswered: the
  // bottom camera is unavailable from now on (the caller counts and logs the fallback once).
  bool finished(const CommandOutcome& outcome);
  // SDK mode entered again (after a reconnection the drone may have restarted with the front camera):
  // the command that puts the wanted camera back, if any.
  std::optional<std::string_view> after_sdk_mode() const;

  bool available() const { return available_; }
  CameraId wanted() const { return wanted_; }

 private:
  bool available_;
  CameraId wanted_ = CameraId::Front;
};

}  // namespace labo::tello
