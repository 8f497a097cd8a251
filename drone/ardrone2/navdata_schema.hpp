#pragma once
// The layout of every navdata option the AR.Drone 2.0 firmware sends (SDK navdata_common.h, sizes
// checked against a real full-mode capture: shared/notes/ardrone.md §2), as data: the parser, the
// builder and the JSON printer all walk these tables, so one table per option is the single place a
// layout is written down. Each field has its wire name, its wire type and count, and, when it has a
// physical unit, the name of its converted value with the unit in it and the scale to get there.
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace labo::ardrone2 {

enum class WireType : std::uint8_t { U8, I16, U16, I32, U32, F32, F64, Bool32 };
std::size_t wire_size(WireType type);

struct FieldSpec {
  constexpr FieldSpec(std::string_view n, WireType t, std::uint8_t c = 1, std::string_view si = {}, double s = 1.0)
      : name(n), type(t), count(c), si_name(si), scale(s) {}
  std::string_view name;     // SDK field name
  WireType type;
  std::uint8_t count;        // array length (matrices flattened row-major)
  std::string_view si_name;  // converted value's name with its unit; empty when dimensionless/raw only
  double scale;              // si = raw * scale
};

struct NavdataOptionSpec {
  std::uint16_t tag;
  std::string_view name;     // snake_case option name (JSON key)
  std::uint16_t size;        // wire size including the 4-byte tag+size header
  std::span<const FieldSpec> fields;
  std::size_t value_count() const;  // sum of field counts
};

enum NavdataTag : std::uint16_t {
  kTagDemo = 0, kTagTime = 1, kTagRawMeasures = 2, kTagPhysMeasures = 3, kTagGyrosOffsets = 4,
  kTagEulerAngles = 5, kTagReferences = 6, kTagTrims = 7, kTagRcReferences = 8, kTagPwm = 9,
  kTagAltitude = 10, kTagVisionRaw = 11, kTagVisionOf = 12, kTagVision = 13, kTagVisionPerf = 14,
  kTagTrackersSend = 15, kTagVisionDetect = 16, kTagWatchdog = 17, kTagAdcDataFrame = 18,
  kTagVideoStream = 19, kTagGames = 20, kTagPressureRaw = 21, kTagMagneto = 22, kTagWindSpeed = 23,
  kTagKalmanPressure = 24, kTagHdvideoStream = 25, kTagWifi = 26, kTagGps = 27,
  kTagChecksum = 0xFFFF,
};
inline constexpr std::size_t kKnownOptionCount = 28;  // tags 0..27
inline constexpr std::uint16_t kOptionHeaderBytes = 4;
inline constexpr std::uint16_t kChecksumOptionBytes = 8;

// Table of every known option, indexed by tag.
std::span<const NavdataOptionSpec> navdata_option_specs();
const NavdataOptionSpec* find_option_spec(std::uint16_t tag);
// Index of a field's first value in the option's flattened value array, or nullopt.
std::optional<std::size_t> field_value_index(const NavdataOptionSpec& spec, std::string_view field_name);

// The 32 state bits by name (bit 24..27 are the four "threads on" flags).
std::string_view state_bit_name(int bit);
inline constexpr int kStateFlying = 0;
inline constexpr int kStateVideoEnabled = 1;
inline constexpr int kStateCommandAck = 6;
inline constexpr int kStateNavdataDemo = 10;
inline constexpr int kStateBootstrap = 11;
inline constexpr int kStateBatteryLow = 15;
inline constexpr int kStateUserEmergency = 16;
inline constexpr int kStateComLost = 13;
inline constexpr int kStateCutout = 22;
inline constexpr int kStateComWatchdog = 30;
inline constexpr int kStateEmergency = 31;
constexpr std::uint32_t state_mask(int bit) { return 1u << bit; }

// Major control states (high 16 bits of demo.ctrl_state).
std::string_view control_state_name(int major);

}  // namespace labo::ardrone2
