#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <vector>

#include "drone/ardrone2/inspect_commands.hpp"
#include "drone/ardrone2/navdata_parser.hpp"
#include "drone/replay/recording.hpp"

namespace labo::ardrone2 {

using replay::Record;
using replay::RecordChannel;
using replay::RecordingError;
using replay::RecordingReader;

using namespace ardrone2;

namespace {

constexpr std::uintmax_t kMaxDatagramFile = 65535;  // a UDP datagram cannot be larger

// Raw integers print as integers; converted values as numbers.
nlohmann::json one_value(double v, bool integer) {
  if (integer) return static_cast<std::int64_t>(v);
  return v;
}

nlohmann::json field_value(const std::vector<double>& raw, std::size_t first, std::size_t count, double scale,
                           bool integer) {
  if (count == 1) return one_value(raw[first] * scale, integer);
  nlohmann::json a = nlohmann::json::array();
  for (std::size_t k = 0; k < count; ++k) a.push_back(one_value(raw[first + k] * scale, integer));
  return a;
}

nlohmann::json option_json(const ardrone2::NavdataOptionSpec& spec, const NavdataOptionValues& values) {
  nlohmann::json o = nlohmann::json::object();
  nlohmann::json raw = nlohmann::json::object();
  std::size_t index = 0;
  for (const auto& f : spec.fields) {
    const bool integer = f.type != WireType::F32 && f.type != WireType::F64;
    raw[std::string(f.name)] = field_value(values.raw, index, f.count, 1.0, integer);
    if (!f.si_name.empty()) o[std::string(f.si_name)] = field_value(values.raw, index, f.count, f.scale, false);
    index += f.count;
  }
  if (spec.tag == kTagDemo) {
    const auto ctrl = static_cast<std::uint32_t>(values.raw[0]);
    o["control_state"] = std::string(control_state_name(control_state_major(ctrl)));
    o["control_state_minor"] = ctrl & 0xFFFFu;
  }
  if (spec.tag == kTagTime) o["time_s"] = navdata_time_seconds(static_cast<std::uint32_t>(values.raw[0]));
  o["size"] = values.wire_size;
  o["raw"] = std::move(raw);
  return o;
}

nlohmann::json packet_json(const NavdataPacket& p) {
  nlohmann::json j;
  j["sequence"] = p.sequence;
  j["magic"] = p.magic;
  j["state"] = p.state;
  nlohmann::json flags = nlohmann::json::object();
  for (int bit = 0; bit < 32; ++bit) flags[std::string(state_bit_name(bit))] = p.state_bit(bit);
  j["state_flags"] = std::move(flags);
  j["vision_defined"] = p.vision_defined;
  j["checksum_ok"] = p.checksum_ok;
  j["checksum_received"] = p.checksum_received;
  j["checksum_computed"] = p.checksum_computed;
  for (const auto& spec : navdata_option_specs()) {
    if (p.has(spec.tag)) j[std::string(spec.name)] = option_json(spec, p.option(spec.tag));
  }
  nlohmann::json unknown = nlohmann::json::array();
  for (const auto& u : p.unknown) unknown.push_back({{"tag", u.tag}, {"size", u.size}});
  j["unknown_options"] = std::move(unknown);
  return j;
}

int print_recording(const std::filesystem::path& file) {
  RecordingReader reader(file);
  Record record;
  NavdataParser parser;
  NavdataPacket packet;
  std::size_t valid = 0, invalid = 0;
  while (reader.next(record)) {
    if (record.channel != RecordChannel::NavdataIn) continue;
    const auto result = parser.parse(record.bytes, packet);
    nlohmann::json j = result.ok() || result.error == NavdataError::BadChecksum ? packet_json(packet) : nlohmann::json::object();
    j["t"] = record.t;
    if (!result.ok()) {
      j["error"] = std::string(to_string(result.error));
      j["detail"] = result.detail;
      ++invalid;
    } else {
      ++valid;
    }
    std::cout << j.dump() << "\n";
  }
  if (reader.truncated()) std::cerr << "labodrone navdata: " << file.string() << ": last record truncated\n";
  if (invalid > 0) std::cerr << "labodrone navdata: " << invalid << " invalid navdata datagrams (see \"error\")\n";
  if (valid == 0) {
    std::cerr << "labodrone navdata: " << file.string() << ": no valid navdata packet in the recording\n";
    return 2;
  }
  return 0;
}

}  // namespace

const CommandSpec& navdata_command_spec() {
  static const CommandSpec spec{
      "navdata", "FILE",
      "Decode AR.Drone navdata: one raw UDP 5554 datagram, or every navdata packet of a recording (JSON lines).",
      {}, 1, 1};
  return spec;
}

int run_navdata_command(const ParsedArgs& args) {
  const std::filesystem::path file = args.positionals.at(0);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) {
    std::cerr << "labodrone navdata: " << file.string() << ": cannot read (" << ec.message() << ")\n";
    return 2;
  }
  try {
    if (RecordingReader::is_recording(file)) return print_recording(file);
  } catch (const RecordingError& e) {
    std::cerr << "labodrone navdata: " << e.what() << "\n";
    return 2;
  }
  if (size > kMaxDatagramFile) {
    std::cerr << "labodrone navdata: " << file.string() << ": " << size
              << " bytes is neither a navdata datagram (<= 65535 bytes) nor a recording\n";
    return 2;
  }
  std::ifstream in(file, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  NavdataPacket packet;
  const auto result = NavdataParser().parse(bytes, packet);
  if (result.ok() || result.error == NavdataError::BadChecksum) std::cout << packet_json(packet).dump() << "\n";
  if (!result.ok()) {
    std::cerr << "labodrone navdata: " << file.string() << ": " << to_string(result.error) << ": " << result.detail << "\n";
    return 2;
  }
  return 0;
}

}  // namespace labo::ardrone2
