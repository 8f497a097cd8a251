#pragma once
// The AR.Drone 2.0's video bit rate keys, for the driver (what to send) and for the firmware's side in
// the emulator and the lockstep sim link (what the drone then streams at). Facts and what is not
// verified on a real drone: docs/ardrone2.md "Video bit rate".
#include <string>
#include <utility>
#include <vector>

namespace labo::ardrone2 {

// The range the SDK's clients accept for video:max_bitrate and video:bitrate (H.264, kbit/s).
inline constexpr int kMinVideoBitrateKbps = 250;
inline constexpr int kMaxVideoBitrateKbps = 4000;
// The firmware's default video:max_bitrate and video:bitrate (SDK Common/config_keys.h).
inline constexpr int kFirmwareVideoBitrateKbps = 1000;

// video:bitrate_ctrl_mode (SDK Common/ardrone_api.h VIDEO_BITRATE_CONTROL_MODE).
enum class VideoBitrateMode {
  FixedToMax = 0,  // VBC_MODE_DISABLED: the stream at video:max_bitrate (the firmware's default mode)
  Dynamic = 1,     // VBC_MODE_DYNAMIC: 250..video:max_bitrate, adapted to the Wi-Fi link
  Manual = 2,      // VBC_MANUAL: the stream at video:bitrate, video:max_bitrate ignored
};

// The AT*CONFIG pairs the driver sends so that the drone streams at `kbps`, in order: the mode first
// (so the new maximum never runs under dynamic control), then video:max_bitrate, then video:bitrate
// (the same rate, should the firmware treat the stream as manual).
std::vector<std::pair<std::string, std::string>> video_bitrate_configs(int kbps);

// The firmware's state of the three keys.
class VideoBitrateControl {
 public:
  explicit VideoBitrateControl(int default_kbps = kFirmwareVideoBitrateKbps)
      : max_kbps_(default_kbps), manual_kbps_(default_kbps) {}
  static bool is_key(const std::string& key);
  // Applies one video:* bit-rate key; false (state unchanged) for a value out of range or not a number.
  bool apply(const std::string& key, const std::string& value);
  // What the encoder is asked for. Dynamic mode adapts to the Wi-Fi link on the drone; the emulator's
  // loopback and the sim link never congest, so it is the maximum there.
  int streaming_kbps() const { return mode_ == VideoBitrateMode::Manual ? manual_kbps_ : max_kbps_; }
  VideoBitrateMode mode() const { return mode_; }

 private:
  VideoBitrateMode mode_ = VideoBitrateMode::FixedToMax;
  int max_kbps_, manual_kbps_;
};

}  // namespace labo::ardrone2
