#include "drone/ardrone2/at_command.hpp"

#include <bit>
#include <charconv>
#include <limits>

namespace labo::ardrone2 {

std::int32_t float_to_at_int(float value) { return std::bit_cast<std::int32_t>(value); }
float at_int_to_float(std::int32_t bits) { return std::bit_cast<float>(bits); }

void AtCommandEncoder::append_int(std::string& out, std::int64_t value) {
  char buf[24];
  const auto result = std::to_chars(buf, buf + sizeof(buf), value);
  out.append(buf, result.ptr);
}

void AtCommandEncoder::append_quoted(std::string& out, std::string_view text) {
  out.push_back('"');
  for (char c : text) {
    // The protocol has no escape: a quote or a line break would end the argument or the command.
    if (c != '"' && c != '\r' && c != '\n') out.push_back(c);
  }
  out.push_back('"');
}

void AtCommandEncoder::begin(std::string& out, std::string_view name) {
  out.append("AT*");
  out.append(name);
  out.push_back('=');
  append_int(out, next_seq_++);
}

void AtCommandEncoder::ref(std::string& out, bool takeoff, bool emergency) {
  std::uint32_t input = kRefBase;
  if (takeoff) input |= kRefTakeoffBit;
  if (emergency) input |= kRefEmergencyBit;
  begin(out, "REF");
  out.push_back(',');
  append_int(out, static_cast<std::int32_t>(input));
  out.push_back('\r');
}

namespace {
float clip_unit(float v) { return v < -1.0f ? -1.0f : (v > 1.0f ? 1.0f : v); }
}  // namespace

void AtCommandEncoder::append_pcmd_values(std::string& out, const WirePcmd& c) {
  // Flag bit 0 clear = hover: the drone ignores the values, which are sent as zeros.
  out.push_back(',');
  append_int(out, c.hover ? 0 : kPcmdProgressive);
  for (float v : {c.roll, c.pitch, c.gaz, c.yaw}) {
    out.push_back(',');
    append_int(out, c.hover ? 0 : float_to_at_int(clip_unit(v)));
  }
}

void AtCommandEncoder::pcmd(std::string& out, const WirePcmd& c) {
  begin(out, "PCMD");
  append_pcmd_values(out, c);
  out.push_back('\r');
}

void AtCommandEncoder::pcmd_mag(std::string& out, const WirePcmd& c, float psi, float psi_accuracy) {
  begin(out, "PCMD_MAG");
  append_pcmd_values(out, c);
  out.push_back(',');
  append_int(out, float_to_at_int(psi));
  out.push_back(',');
  append_int(out, float_to_at_int(psi_accuracy));
  out.push_back('\r');
}

void AtCommandEncoder::ftrim(std::string& out) {
  begin(out, "FTRIM");
  out.push_back('\r');
}

void AtCommandEncoder::config(std::string& out, std::string_view key, std::string_view value) {
  begin(out, "CONFIG");
  out.push_back(',');
  append_quoted(out, key);
  out.push_back(',');
  append_quoted(out, value);
  out.push_back('\r');
}

void AtCommandEncoder::config_ids(std::string& out, std::string_view session, std::string_view profile,
                                  std::string_view application) {
  begin(out, "CONFIG_IDS");
  for (auto id : {session, profile, application}) {
    out.push_back(',');
    append_quoted(out, id);
  }
  out.push_back('\r');
}

void AtCommandEncoder::comwdg(std::string& out) {
  begin(out, "COMWDG");
  out.push_back('\r');
}

void AtCommandEncoder::calib(std::string& out, int device) {
  begin(out, "CALIB");
  out.push_back(',');
  append_int(out, device);
  out.push_back('\r');
}

void AtCommandEncoder::ctrl(std::string& out, int mode) {
  begin(out, "CTRL");
  out.push_back(',');
  append_int(out, mode);
  out.append(",0\r");
}

int at_expected_args(std::string_view name) {
  if (name == "REF") return 1;
  if (name == "PCMD") return 5;
  if (name == "PCMD_MAG") return 7;
  if (name == "FTRIM" || name == "COMWDG") return 0;
  if (name == "CONFIG") return 2;
  if (name == "CONFIG_IDS") return 3;
  if (name == "CALIB") return 1;
  if (name == "CTRL") return 2;
  return -1;
}

namespace {

bool parse_int32(std::string_view text, std::int32_t& value) {
  if (text.empty()) return false;
  std::int64_t wide = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), wide);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return false;
  // Unsigned values above INT32_MAX (a REF input printed unsigned) wrap like the firmware's atoi.
  if (wide < std::numeric_limits<std::int32_t>::min() || wide > std::numeric_limits<std::uint32_t>::max())
    return false;
  value = static_cast<std::int32_t>(static_cast<std::uint32_t>(wide));
  return true;
}

bool is_name_char(char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; }

}  // namespace

bool AtCommandParser::parse_one(std::string_view text, AtCommand& command, std::string& error) {
  if (!text.starts_with("AT*")) {
    error = "command does not start with AT*";
    return false;
  }
  text.remove_prefix(3);
  const std::size_t eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    error = "command has no '=<seq>'";
    return false;
  }
  const std::string_view name = text.substr(0, eq);
  for (char c : name) {
    if (!is_name_char(c)) {
      error = "command name has a character outside [A-Z0-9_]";
      return false;
    }
  }
  command.name.assign(name);
  std::string_view rest = text.substr(eq + 1);
  const std::size_t comma = rest.find(',');
  std::int32_t seq = 0;
  if (!parse_int32(rest.substr(0, comma), seq) || seq <= 0) {
    error = "sequence number is not a positive integer";
    return false;
  }
  command.sequence = static_cast<std::uint32_t>(seq);
  std::size_t n = 0;
  rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
  bool more = comma != std::string_view::npos;
  while (more) {
    if (n == command.args.size()) command.args.emplace_back();
    AtArgument& arg = command.args[n++];
    if (!rest.empty() && rest.front() == '"') {
      const std::size_t close = rest.find('"', 1);
      if (close == std::string_view::npos) {
        error = "unterminated string argument";
        return false;
      }
      arg.is_string = true;
      arg.text.assign(rest.substr(1, close - 1));
      rest.remove_prefix(close + 1);
      if (!rest.empty() && rest.front() != ',') {
        error = "text after a string argument";
        return false;
      }
    } else {
      const std::size_t end = rest.find(',');
      arg.is_string = false;
      arg.text.clear();
      if (!parse_int32(rest.substr(0, end), arg.integer)) {
        error = "argument is neither an int32 nor a quoted string";
        return false;
      }
      rest = end == std::string_view::npos ? std::string_view() : rest.substr(end);
    }
    more = !rest.empty();
    if (more) rest.remove_prefix(1);  // the comma
  }
  command.args.resize(n);
  const int expected = at_expected_args(command.name);
  if (expected >= 0 && static_cast<std::size_t>(expected) != n) {
    error = "AT*" + command.name + " takes " + std::to_string(expected) + " arguments, got " + std::to_string(n);
    return false;
  }
  return true;
}

AtParseReport AtCommandParser::parse(std::string_view datagram, std::vector<AtCommand>& out) const {
  AtParseReport report;
  std::size_t used = 0;
  if (datagram.size() > kMaxAtDatagramBytes) {
    report.datagram_too_long = true;
    report.first_error = "datagram of " + std::to_string(datagram.size()) + " bytes exceeds 1024";
    out.clear();
    return report;
  }
  std::string error;
  std::size_t pos = 0;
  while (pos < datagram.size()) {
    const std::size_t end = datagram.find_first_of("\r\n", pos);
    if (end == pos) {  // CR LF pairs and blank lines
      ++pos;
      continue;
    }
    if (end == std::string_view::npos) {
      ++report.malformed;
      if (report.first_error.empty()) report.first_error = "command without CR or LF terminator";
      break;
    }
    if (used == out.size()) out.emplace_back();
    if (parse_one(datagram.substr(pos, end - pos), out[used], error)) {
      ++used;
      ++report.commands;
    } else {
      ++report.malformed;
      if (report.first_error.empty()) report.first_error = error;
    }
    pos = end + 1;
  }
  out.resize(used);
  return report;
}

bool AtSequenceFilter::accept(std::uint32_t seq) {
  if (seq == 1 || seq > last_) {
    last_ = seq;
    return true;
  }
  return false;
}

}  // namespace labo::ardrone2
