#pragma once
// The Tello's state string (SDK 2.0, UDP 8890, ~10 Hz): "key:value;" pairs ending in "\r\n",
//   [mid:%d;x:%d;y:%d;z:%d;mpry:%d,%d,%d;]pitch:%d;roll:%d;yaw:%d;vgx:%d;vgy:%d;vgz:%d;
//   templ:%d;temph:%d;tof:%d;h:%d;bat:%d;baro:%.2f;time:%d;agx:%.2f;agy:%.2f;agz:%.2f;\r\n
// in the drone's own units and signs (docs/tello.md). TelloStateParser reads one datagram into a
// TelloState with every field bounded; a string it refuses gets a TelloStateError naming the field
// and what was expected (the link counts them by kind). It never allocates on the good path.
// format_tello_state() writes the string back (the emulator, fixtures).
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace labo::tello {

inline constexpr std::size_t kMaxStateBytes = 512;  // a full string with mission-pad fields is ~190

struct TelloState {
  // Mission pad (Tello EDU with "mon"): present only when the string carries the five fields.
  bool has_mission_pad = false;
  int mid = -2;                        // pad id 1-8; -1 none detected, -2 detection off
  double x_cm = 0, y_cm = 0, z_cm = 0;  // relative to the pad
  std::array<double, 3> mpry_deg{};     // pitch, roll, yaw relative to the pad
  double pitch_deg = 0;  // > 0 nose up
  double roll_deg = 0;   // > 0 right wing down
  double yaw_deg = 0;    // > 0 clockwise seen from above
  double vgx_dmps = 0, vgy_dmps = 0, vgz_dmps = 0;  // x forward, y right, z down
  double templ_c = 0, temph_c = 0;
  double tof_cm = 0;     // time-of-flight range to the surface below
  double h_cm = 0;       // height above the take-off point
  double bat_percent = 0;
  double baro_cm = 0;    // barometric altitude
  double time_s = 0;     // motors-on time
  double agx_mg = 0, agy_mg = 0, agz_mg = 0;  // specific force, 0.001 g; about -1000 on z at rest
};

enum class TelloStateError {
  None,
  Empty,           // no bytes
  TooLong,         // more than kMaxStateBytes
  NotText,         // a byte outside printable ASCII before the final line break
  Unterminated,    // the last field has no ';' (a datagram cut short)
  MalformedField,  // a field without "key:value"
  DuplicateField,
  BadNumber,       // not a finite number, or text after it
  OutOfRange,
  MissingField,    // a required field absent, or some mission-pad fields without the others
};
// Counter kind, e.g. "tello_state_missing_field".
std::string_view to_string(TelloStateError error);

struct TelloStateParseResult {
  TelloStateError error = TelloStateError::None;
  std::string detail;              // set only on error (allocation only on the bad path)
  std::size_t unknown_fields = 0;  // well-formed fields of keys this parser does not know (ignored)
  bool ok() const { return error == TelloStateError::None; }
};

class TelloStateParser {
 public:
  TelloStateParseResult parse(std::span<const std::uint8_t> datagram, TelloState& state) const;
  TelloStateParseResult parse(std::string_view text, TelloState& state) const;
};

// The string a Tello sends for `state` (integers rounded, baro and ag* with two decimals), "\r\n"
// included, into `out` (its capacity reused).
void format_tello_state(const TelloState& state, std::string& out);

}  // namespace labo::tello
