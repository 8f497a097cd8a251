#pragma once
// "rc a b c d": the Tello's four sticks, each an integer in [-100, 100] (SDK 2.0): a left/right
// (> 0 right), b backward/forward (> 0 forward), c down/up (> 0 up), d yaw (> 0 clockwise). Written by
// TelloLink many times a second; read by the emulator and the replay.
#include <string>
#include <string_view>

namespace labo::tello {

struct RcSticks {
  int a = 0;  // left/right
  int b = 0;  // backward/forward
  int c = 0;  // down/up
  int d = 0;  // yaw: counter-clockwise/clockwise
  bool centred() const { return a == 0 && b == 0 && c == 0 && d == 0; }
  bool operator==(const RcSticks&) const = default;
};

inline constexpr int kMaxStick = 100;

// "rc a b c d" into `out` (its capacity reused).
void format_rc(const RcSticks& sticks, std::string& out);
// The four integers after "rc ", each in [-100, 100]; false for anything else.
bool parse_rc_arguments(std::string_view arguments, RcSticks& sticks);

}  // namespace labo::tello
