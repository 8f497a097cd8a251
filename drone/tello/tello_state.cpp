#include "drone/tello/tello_state.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace labo::tello {

namespace {

enum class Slot { Member, Mid, Mpry };

struct FieldSpec {
  std::string_view key;
  Slot slot;
  double TelloState::*member;
  double min, max;
  bool mission_pad;
};

// Bounds: what a flying Tello can report, with margin; anything beyond is a corrupt string.
constexpr FieldSpec kFields[] = {
    {"mid", Slot::Mid, nullptr, -2, 8, true},
    {"x", Slot::Member, &TelloState::x_cm, -1000, 1000, true},
    {"y", Slot::Member, &TelloState::y_cm, -1000, 1000, true},
    {"z", Slot::Member, &TelloState::z_cm, -1000, 1000, true},
    {"mpry", Slot::Mpry, nullptr, -360, 360, true},
    {"pitch", Slot::Member, &TelloState::pitch_deg, -180, 180, false},
    {"roll", Slot::Member, &TelloState::roll_deg, -180, 180, false},
    {"yaw", Slot::Member, &TelloState::yaw_deg, -180, 180, false},
    {"vgx", Slot::Member, &TelloState::vgx_dmps, -200, 200, false},
    {"vgy", Slot::Member, &TelloState::vgy_dmps, -200, 200, false},
    {"vgz", Slot::Member, &TelloState::vgz_dmps, -200, 200, false},
    {"templ", Slot::Member, &TelloState::templ_c, -40, 150, false},
    {"temph", Slot::Member, &TelloState::temph_c, -40, 150, false},
    {"tof", Slot::Member, &TelloState::tof_cm, 0, 10000, false},
    {"h", Slot::Member, &TelloState::h_cm, -10000, 10000, false},
    {"bat", Slot::Member, &TelloState::bat_percent, 0, 100, false},
    {"baro", Slot::Member, &TelloState::baro_cm, -100000, 1000000, false},
    {"time", Slot::Member, &TelloState::time_s, 0, 100000, false},
    {"agx", Slot::Member, &TelloState::agx_mg, -16000, 16000, false},
    {"agy", Slot::Member, &TelloState::agy_mg, -16000, 16000, false},
    {"agz", Slot::Member, &TelloState::agz_mg, -16000, 16000, false},
};
constexpr std::size_t kFieldCount = std::size(kFields);
static_assert(kFieldCount <= 32, "seen fields are a 32-bit mask");

constexpr std::uint32_t mask_of(bool mission_pad) {
  std::uint32_t m = 0;
  for (std::size_t i = 0; i < kFieldCount; ++i)
    if (kFields[i].mission_pad == mission_pad) m |= 1u << i;
  return m;
}
constexpr std::uint32_t kRequired = mask_of(false);
constexpr std::uint32_t kMissionPad = mask_of(true);

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

bool valid_key(std::string_view key) {
  if (key.empty()) return false;
  for (char c : key)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

const FieldSpec* find_field(std::string_view key, std::size_t& index) {
  for (index = 0; index < kFieldCount; ++index)
    if (kFields[index].key == key) return &kFields[index];
  return nullptr;
}

TelloStateParseResult fail(TelloStateError error, std::string detail) {
  TelloStateParseResult r;
  r.error = error;
  r.detail = std::move(detail);
  return r;
}

std::string range_text(const FieldSpec& f) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "[%g, %g]", f.min, f.max);
  return buf;
}

// One number of a field, finite and within the field's bounds.
TelloStateParseResult read_number(const FieldSpec& f, std::string_view text, double& value) {
  text = trim(text);
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value))
    return fail(TelloStateError::BadNumber,
                "field '" + std::string(f.key) + "': '" + std::string(text) + "' is not a finite number");
  if (value < f.min || value > f.max)
    return fail(TelloStateError::OutOfRange,
                "field '" + std::string(f.key) + "': " + std::string(text) + " outside " + range_text(f));
  return {};
}

TelloStateParseResult read_field(const FieldSpec& f, std::string_view value, TelloState& state) {
  if (f.slot == Slot::Mpry) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t comma = value.find(',');
      if ((k < 2) != (comma != std::string_view::npos))
        return fail(TelloStateError::BadNumber,
                    "field 'mpry': '" + std::string(value) + "' is not three numbers separated by commas");
      auto r = read_number(f, value.substr(0, comma), state.mpry_deg[k]);
      if (!r.ok()) return r;
      value = comma == std::string_view::npos ? std::string_view() : value.substr(comma + 1);
    }
    return {};
  }
  double v = 0;
  auto r = read_number(f, value, v);
  if (!r.ok()) return r;
  if (f.slot == Slot::Mid) {
    state.mid = static_cast<int>(std::lround(v));
  } else {
    state.*f.member = v;
  }
  return {};
}

// Strips the final line break; true when the rest is printable ASCII.
bool strip_and_check_text(std::string_view& text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
  for (char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) return false;
  return true;
}

}  // namespace

std::string_view to_string(TelloStateError error) {
  switch (error) {
    case TelloStateError::None: return "tello_state_ok";
    case TelloStateError::Empty: return "tello_state_empty";
    case TelloStateError::TooLong: return "tello_state_too_long";
    case TelloStateError::NotText: return "tello_state_not_text";
    case TelloStateError::Unterminated: return "tello_state_unterminated";
    case TelloStateError::MalformedField: return "tello_state_malformed_field";
    case TelloStateError::DuplicateField: return "tello_state_duplicate_field";
    case TelloStateError::BadNumber: return "tello_state_bad_number";
    case TelloStateError::OutOfRange: return "tello_state_out_of_range";
    case TelloStateError::MissingField: return "tello_state_missing_field";
  }
  return "tello_state_error";
}

TelloStateParseResult TelloStateParser::parse(std::span<const std::uint8_t> datagram, TelloState& state) const {
  return parse(std::string_view(reinterpret_cast<const char*>(datagram.data()), datagram.size()), state);
}

TelloStateParseResult TelloStateParser::parse(std::string_view text, TelloState& state) const {
  if (text.empty()) return fail(TelloStateError::Empty, "empty datagram");
  if (text.size() > kMaxStateBytes)
    return fail(TelloStateError::TooLong,
                std::to_string(text.size()) + " bytes, a state string has at most " + std::to_string(kMaxStateBytes));
  if (!strip_and_check_text(text))
    return fail(TelloStateError::NotText, "a byte outside printable ASCII (expected \"key:value;\" text)");
  TelloState parsed;
  TelloStateParseResult result;
  std::uint32_t seen = 0;
  while (!trim(text).empty()) {
    const std::size_t semi = text.find(';');
    if (semi == std::string_view::npos)
      return fail(TelloStateError::Unterminated, "'" + std::string(trim(text)) + "' has no ';' (string cut short?)");
    const std::string_view item = trim(text.substr(0, semi));
    text.remove_prefix(semi + 1);
    const std::size_t colon = item.find(':');
    const std::string_view key = colon == std::string_view::npos ? item : trim(item.substr(0, colon));
    if (colon == std::string_view::npos || !valid_key(key))
      return fail(TelloStateError::MalformedField, "'" + std::string(item) + "' is not \"key:value\"");
    std::size_t index = 0;
    const FieldSpec* f = find_field(key, index);
    if (!f) {
      ++result.unknown_fields;
      continue;
    }
    if (seen & (1u << index)) return fail(TelloStateError::DuplicateField, "field '" + std::string(key) + "' twice");
    seen |= 1u << index;
    auto r = read_field(*f, item.substr(colon + 1), parsed);
    if (!r.ok()) return r;
  }
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    if ((kRequired & (1u << i)) && !(seen & (1u << i)))
      return fail(TelloStateError::MissingField, "missing field '" + std::string(kFields[i].key) + "'");
  }
  const std::uint32_t pad = seen & kMissionPad;
  if (pad != 0 && pad != kMissionPad)
    return fail(TelloStateError::MissingField, "mission-pad fields mid, x, y, z, mpry must come together");
  parsed.has_mission_pad = pad != 0;
  state = parsed;
  return result;
}

void format_tello_state(const TelloState& s, std::string& out) {
  auto i = [](double v) { return static_cast<long>(std::lround(v)); };
  char buf[kMaxStateBytes];
  int n = 0;
  if (s.has_mission_pad) {
    n = std::snprintf(buf, sizeof(buf), "mid:%d;x:%ld;y:%ld;z:%ld;mpry:%ld,%ld,%ld;", s.mid, i(s.x_cm), i(s.y_cm),
                      i(s.z_cm), i(s.mpry_deg[0]), i(s.mpry_deg[1]), i(s.mpry_deg[2]));
  }
  n += std::snprintf(buf + n, sizeof(buf) - static_cast<std::size_t>(n),
                     "pitch:%ld;roll:%ld;yaw:%ld;vgx:%ld;vgy:%ld;vgz:%ld;templ:%ld;temph:%ld;tof:%ld;h:%ld;bat:%ld;"
                     "baro:%.2f;time:%ld;agx:%.2f;agy:%.2f;agz:%.2f;\r\n",
                     i(s.pitch_deg), i(s.roll_deg), i(s.yaw_deg), i(s.vgx_dmps), i(s.vgy_dmps), i(s.vgz_dmps),
                     i(s.templ_c), i(s.temph_c), i(s.tof_cm), i(s.h_cm), i(s.bat_percent), s.baro_cm, i(s.time_s),
                     s.agx_mg, s.agy_mg, s.agz_mg);
  out.assign(buf, static_cast<std::size_t>(std::min<int>(n, static_cast<int>(sizeof(buf)) - 1)));
}

}  // namespace labo::tello
