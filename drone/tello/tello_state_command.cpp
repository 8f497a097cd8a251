#include "drone/tello/tello_state_command.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "drone/replay/recording.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo::tello {

using replay::Record;
using replay::RecordChannel;
using replay::RecordingError;
using replay::RecordingReader;

using namespace tello;

namespace {

constexpr std::uintmax_t kMaxCaptureBytes = 64u << 20;

nlohmann::json state_object(const TelloState& s) {
  nlohmann::json j{{"pitch_deg", s.pitch_deg}, {"roll_deg", s.roll_deg},   {"yaw_deg", s.yaw_deg},
                   {"vgx_dmps", s.vgx_dmps},   {"vgy_dmps", s.vgy_dmps},   {"vgz_dmps", s.vgz_dmps},
                   {"templ_c", s.templ_c},     {"temph_c", s.temph_c},     {"tof_cm", s.tof_cm},
                   {"h_cm", s.h_cm},           {"bat_percent", s.bat_percent}, {"baro_cm", s.baro_cm},
                   {"time_s", s.time_s},       {"agx_mg", s.agx_mg},       {"agy_mg", s.agy_mg},
                   {"agz_mg", s.agz_mg}};
  if (s.has_mission_pad) {
    j["mission_pad"] = {{"mid", s.mid}, {"x_cm", s.x_cm}, {"y_cm", s.y_cm}, {"z_cm", s.z_cm}, {"mpry_deg", s.mpry_deg}};
  }
  return j;
}

nlohmann::json sample_object(const TelloState& s) {
  NavdataSample n;
  sample_from_state(s, 0.0, 0, 0, n);
  return {{"roll_rad", n.roll_rad},     {"pitch_rad", n.pitch_rad}, {"yaw_rad", n.yaw_rad},
          {"altitude_m", n.altitude_m}, {"vx_mps", n.vx_mps},       {"vy_mps", n.vy_mps},
          {"vz_mps", n.vz_mps},         {"battery_percent", n.battery_percent}};
}

struct Tally {
  std::size_t valid = 0, invalid = 0;
};

// Prints one string's line; `where` holds "line" or "t".
void print_one(std::string_view text, nlohmann::json where, Tally& tally) {
  TelloState state;
  const TelloStateParseResult r = TelloStateParser().parse(text, state);
  nlohmann::json j = std::move(where);
  if (r.ok()) {
    j["state"] = state_object(state);
    j["sample"] = sample_object(state);
    if (r.unknown_fields > 0) j["unknown_fields"] = r.unknown_fields;
    ++tally.valid;
  } else {
    j["error"] = std::string(to_string(r.error));
    j["detail"] = r.detail;
    ++tally.invalid;
  }
  std::cout << j.dump() << "\n";
}

Tally print_recording(const std::filesystem::path& file, bool& truncated) {
  RecordingReader reader(file);
  Record record;
  Tally tally;
  while (reader.next(record)) {
    if (record.channel != RecordChannel::TelloStateIn) continue;
    print_one(std::string_view(reinterpret_cast<const char*>(record.bytes.data()), record.bytes.size()),
              nlohmann::json{{"t", record.t}}, tally);
  }
  truncated = reader.truncated();
  return tally;
}

Tally print_lines(std::ifstream& in) {
  Tally tally;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line == "\r") continue;
    print_one(line, nlohmann::json{{"line", n}}, tally);
  }
  return tally;
}

}  // namespace

const CommandSpec& tello_state_command_spec() {
  static const CommandSpec spec{
      "tello-state", "FILE",
      "Decode Tello state strings: a capture (one per line) or a recording's (JSON lines, drone units and SI).",
      {}, 1, 1};
  return spec;
}

int run_tello_state_command(const ParsedArgs& args) {
  const std::filesystem::path file = args.positionals.at(0);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) {
    std::cerr << "labodrone tello-state: " << file.string() << ": cannot read (" << ec.message() << ")\n";
    return 2;
  }
  Tally tally;
  bool truncated = false;
  try {
    if (RecordingReader::is_recording(file)) {
      tally = print_recording(file, truncated);
    } else if (size > kMaxCaptureBytes) {
      std::cerr << "labodrone tello-state: " << file.string() << ": " << size
                << " bytes is neither a capture of state strings (<= 64 MiB) nor a recording\n";
      return 2;
    } else {
      std::ifstream in(file, std::ios::binary);
      tally = print_lines(in);
    }
  } catch (const RecordingError& e) {
    std::cerr << "labodrone tello-state: " << e.what() << "\n";
    return 2;
  }
  if (truncated) std::cerr << "labodrone tello-state: " << file.string() << ": last record truncated\n";
  if (tally.valid == 0) {
    std::cerr << "labodrone tello-state: " << file.string() << ": no valid Tello state string ("
              << tally.invalid << " refused, see \"error\")\n";
    return 2;
  }
  if (tally.invalid > 0) std::cerr << "labodrone tello-state: " << tally.invalid << " invalid state strings (see \"error\")\n";
  return 0;
}

}  // namespace labo::tello
