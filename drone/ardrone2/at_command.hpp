#pragma once
// AT commands (UDP 5556): the encoder the driver uses and the parser the emulator and the fuzzer use.
// Wire facts (shared/notes/ardrone.md §1): `AT*NAME=<seq>[,args]` ended by CR (the SDK) or LF (the
// guide); one datagram <= 1024 bytes carries whole commands only; floats travel as their IEEE-754
// bits printed as a signed int32; one sequence counter starting at 1; seq 1 resets the drone's
// counter, and commands not above the last accepted seq are dropped.
//
// The encoder speaks the AR.Drone's own signs (PCMD pitch < 0 = forward, yaw > 0 = clockwise): the
// conversion from LaboDrone's MoveCommand lives in wire_signs.hpp.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace labo::ardrone2 {

inline constexpr std::size_t kMaxAtDatagramBytes = 1024;
// AT*REF input: bits 18, 20, 22, 24, 28 always set (2-bit trim/X/Y fields stored as value+1).
inline constexpr std::uint32_t kRefBase = 0x11540000u;
inline constexpr std::uint32_t kRefTakeoffBit = 1u << 9;
inline constexpr std::uint32_t kRefEmergencyBit = 1u << 8;
// AT*PCMD flag bits.
inline constexpr int kPcmdProgressive = 1;      // use the values (0 = hover)
inline constexpr int kPcmdCombinedYaw = 2;
inline constexpr int kPcmdAbsoluteControl = 4;  // magneto mode (PCMD_MAG)
// AT*CTRL modes.
inline constexpr int kCtrlGetConfig = 4;
inline constexpr int kCtrlAckConfig = 5;

std::int32_t float_to_at_int(float value);
float at_int_to_float(std::int32_t bits);

// Progressive command in the drone's signs, each in [-1, 1].
struct WirePcmd {
  bool hover = true;
  float roll = 0, pitch = 0, gaz = 0, yaw = 0;
};

// Appends commands to a caller-owned buffer (its capacity reused, so the 30 ms loop does not
// allocate), numbering them from one counter.
class AtCommandEncoder {
 public:
  // The next command gets seq 1 again (the drone resets its counter on seq 1).
  void reset_sequence() { next_seq_ = 1; }
  std::uint32_t next_sequence() const { return next_seq_; }

  void ref(std::string& out, bool takeoff, bool emergency);
  void pcmd(std::string& out, const WirePcmd& command);
  void pcmd_mag(std::string& out, const WirePcmd& command, float psi, float psi_accuracy);
  void ftrim(std::string& out);
  void config(std::string& out, std::string_view key, std::string_view value);
  void config_ids(std::string& out, std::string_view session, std::string_view profile,
                  std::string_view application);
  void comwdg(std::string& out);
  void calib(std::string& out, int device);
  void ctrl(std::string& out, int mode);

 private:
  void begin(std::string& out, std::string_view name);
  static void append_int(std::string& out, std::int64_t value);
  static void append_pcmd_values(std::string& out, const WirePcmd& command);
  static void append_quoted(std::string& out, std::string_view text);
  std::uint32_t next_seq_ = 1;
};

// One parsed command. Arguments keep their wire text; strings are unquoted.
struct AtArgument {
  bool is_string = false;
  std::int32_t integer = 0;  // valid when !is_string
  std::string text;          // the string's content when is_string
};

struct AtCommand {
  std::string name;  // "REF", "PCMD", ...
  std::uint32_t sequence = 0;
  std::vector<AtArgument> args;

  float float_arg(std::size_t i) const { return at_int_to_float(args.at(i).integer); }
};

struct AtParseReport {
  bool datagram_too_long = false;  // > 1024 bytes: rejected whole
  std::size_t commands = 0;        // well-formed commands appended
  std::size_t malformed = 0;       // commands skipped (bad syntax, bad number, unterminated)
  std::string first_error;         // empty when none
};

class AtCommandParser {
 public:
  // Parses a datagram into `out` (cleared first; its elements' storage is reused).
  AtParseReport parse(std::string_view datagram, std::vector<AtCommand>& out) const;

 private:
  static bool parse_one(std::string_view text, AtCommand& command, std::string& error);
};

// The drone's sequence rule: accept seq 1 (a reset) or anything above the last accepted seq.
class AtSequenceFilter {
 public:
  bool accept(std::uint32_t seq);
  std::uint32_t last() const { return last_; }

 private:
  std::uint32_t last_ = 0;
};

// Expected argument count per known command; -1 for unknown names.
int at_expected_args(std::string_view name);

}  // namespace labo::ardrone2
