#pragma once
// TelloFirmware: what a Tello in SDK 2.0 mode does with the text commands it receives, played over
// any EmulatedVehicle (the simulated lab), without I/O. TelloEmulator (tello_emulator.hpp) puts it
// on UDP; tests drive it directly. Behaviour played (docs/tello.md "TelloEmulator"):
//   - nothing is answered before "command" (SDK mode); then every command but "rc" gets one reply;
//   - setup and read commands are answered after `reply_delay_s`; takeoff once the vehicle hovers,
//     land once it is down (or "error" after `motion_timeout_s`), emergency at once;
//   - "rc a b c d" moves the vehicle (centred sticks: hover) and is never answered;
//   - the 15 s watchdog: a flying vehicle without any command for `watchdog_s` lands;
//   - while a take-off or landing runs, other commands get "error" (emergency and rc excepted);
//   - "downvision 0|1" (a Tello EDU) switches the stream between the front and the downward camera
//     (render_stream), answered "ok"; a plain Tello (`downvision` false) answers "error";
//   - the SDK's distance moves (up/down/left/right/forward/back/cw/ccw/go/curve/flip, tello_moves.hpp)
//     are flown over the vehicle's own odometry and answered "ok" once done ("error" with the reason
//     for arguments out of range, "error" after the move's time); "stop" ends one, "rc" is ignored
//     while one runs;
//   - unknown commands, bad arguments and what this emulator does not fly (jump, the mission pads,
//     wifi) get "error", counted.
// The caller serialises every call (one lock with the vehicle's).
#include <optional>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

#include "drone/ardrone2/link_counters.hpp"
#include "drone/emulated_vehicle.hpp"
#include "drone/tello/tello_moves.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo::tello {

struct TelloFirmwareSettings {
  Seconds reply_delay_s = 0.02;     // a setup or read command's answer
  Seconds watchdog_s = 15.0;        // a flying Tello without commands this long lands
  Seconds motion_timeout_s = 10.0;  // a take-off or landing not done by then is answered "error"
  bool downvision = true;           // a Tello EDU: "downvision 0|1" switches to the downward camera
};

class TelloFirmware {
 public:
  TelloFirmware(TelloFirmwareSettings settings, ardrone2::LinkCounters& counters);

  struct Reply {
    std::string text;
    Seconds due_t = 0;  // send at or after this time
  };
  // One command datagram's text, received at t. Returns the reply to send, if one is due (a motion
  // command's reply comes later from advance()).
  std::optional<Reply> command(std::string_view text, EmulatedVehicle& vehicle, Seconds t);
  // Time passes (call often): a take-off or landing completes, the watchdog lands the vehicle, the
  // motors' time and the height above the take-off point are kept.
  std::optional<Reply> advance(EmulatedVehicle& vehicle, Seconds t);

  bool sdk_mode() const { return sdk_mode_; }
  bool streaming() const { return streaming_; }
  // A new "streamon" since the last call: the video starts over with an IDR.
  bool take_stream_restart();
  bool down_vision() const { return down_vision_; }
  // The streamed camera's picture now: the front camera's, or after "downvision 1" the downward
  // camera's, grey, kDownvisionWidth x kDownvisionHeight. `bgr` is reused when its size fits.
  void render_stream(EmulatedVehicle& vehicle, cv::Mat& bgr);
  // The state string now.
  TelloState state(const VehicleTelemetry& telemetry) const;

 private:
  enum class Motion { None, TakingOff, Landing, Moving };
  std::optional<Reply> handle(std::string_view word, std::string_view args, EmulatedVehicle& vehicle, Seconds t);
  std::optional<Reply> rc(std::string_view args, EmulatedVehicle& vehicle, Seconds t);
  std::optional<Reply> downvision(std::string_view args, Seconds t);
  std::optional<Reply> start_move(const MoveParse& move, const VehicleTelemetry& tel, Seconds t);
  std::optional<Reply> fly_move(EmulatedVehicle& vehicle, Seconds t);
  void update_odometry(const VehicleTelemetry& tel, Seconds t);
  std::optional<Reply> read(std::string_view word, const VehicleTelemetry& telemetry, Seconds t) const;
  Reply after_delay(std::string text, Seconds t) const { return Reply{std::move(text), t + settings_.reply_delay_s}; }

  TelloFirmwareSettings settings_;
  ardrone2::LinkCounters& counters_;
  bool sdk_mode_ = false;
  bool streaming_ = false;
  bool stream_restart_ = false;
  bool down_vision_ = false;
  cv::Mat down_render_, down_sized_, down_grey_;  // render_stream's scratch
  int speed_cmps_ = 10;
  Motion motion_ = Motion::None;
  Seconds motion_since_ = 0;
  Seconds last_command_t_ = 0;
  Seconds last_advance_t_ = -1;
  double motors_s_ = 0;
  double takeoff_pressure_pa_ = -1;  // latched at take-off: the height's reference
  double height_m_ = 0;
  MoveOdometry odometry_;             // the vehicle's own account of where it is, for the moves
  std::optional<MoveFlight> move_;    // the distance move flown (motion_ Moving)
  std::optional<Reply> deferred_;     // a reply advance() sends (stop's, after the move it ended)
};

}  // namespace labo::tello
