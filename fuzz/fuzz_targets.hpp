#pragma once
// The bodies of the libFuzzer harnesses (fuzz/*_fuzzer.cpp), shared with the regression test that
// replays tests/data/fuzz/ in the normal test suite. Each returns false when a property is broken
// (the fuzzers then trap); crashes and sanitizer reports are caught by the fuzzer itself.
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "drone/ardrone2/at_command.hpp"
#include "drone/ardrone2/navdata_builder.hpp"
#include "drone/ardrone2/navdata_parser.hpp"
#include "drone/ardrone2/pave.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_command.hpp"
#include "drone/tello/tello_state.hpp"
#include "drone/tello/tello_rc.hpp"

namespace labo::fuzz {

// Navdata: never reads out of bounds; a packet that parses rebuilds to a packet with the same values.
inline bool navdata_target(std::span<const std::uint8_t> data) {
  using namespace ardrone2;
  NavdataPacket packet, again;
  const auto result = NavdataParser().parse(data, packet);
  if (!result.ok()) return !result.detail.empty();
  std::vector<std::uint8_t> rebuilt;
  NavdataBuilder().build(packet, rebuilt);
  if (!NavdataParser().parse(rebuilt, again).ok()) return false;
  for (const auto& spec : navdata_option_specs()) {
    if (packet.has(spec.tag) != again.has(spec.tag)) return false;
    if (!packet.has(spec.tag)) continue;
    const auto& a = packet.option(spec.tag).raw;
    const auto& b = again.option(spec.tag).raw;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
    }
  }
  return again.sequence == packet.sequence && again.state == packet.state;
}

// PaVE: fed whole or in chunks (sizes from the first byte), the demuxer yields the same frames, each
// within the payload limit, and never keeps more than the stream it was given.
inline bool pave_target(std::span<const std::uint8_t> data) {
  using namespace ardrone2;
  if (data.empty()) return true;
  const std::size_t step = 1 + data[0] % 97;
  const auto stream = data.subspan(1);
  constexpr std::size_t kLimit = 64 * 1024;
  auto demux = [&](std::size_t chunk, std::vector<std::vector<std::uint8_t>>& frames) {
    PaveDemuxer d(kLimit);
    PaveFrame f;
    for (std::size_t pos = 0; pos < stream.size(); pos += chunk) {
      d.feed(stream.subspan(pos, std::min(chunk, stream.size() - pos)));
      for (PaveStatus s; (s = d.next(f)) != PaveStatus::NeedMore;) {
        if (s == PaveStatus::Frame) {
          if (f.payload.size() > kLimit * 255) return false;
          frames.emplace_back(f.payload.begin(), f.payload.end());
        }
      }
      if (d.buffered_bytes() > stream.size()) return false;
    }
    return true;
  };
  std::vector<std::vector<std::uint8_t>> whole, chunked;
  if (!demux(stream.size() + 1, whole) || !demux(step, chunked)) return false;
  return whole == chunked;
}

// AT: the parser accounts for every command line and each parsed command re-encodes to itself.
inline bool at_target(std::span<const std::uint8_t> data) {
  using namespace ardrone2;
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  std::vector<AtCommand> commands;
  const auto report = AtCommandParser().parse(text, commands);
  if (report.datagram_too_long) return data.size() > kMaxAtDatagramBytes && commands.empty();
  if (report.commands != commands.size()) return false;
  AtSequenceFilter filter;
  for (const auto& c : commands) {
    if (c.sequence == 0 || c.name.empty()) return false;
    filter.accept(c.sequence);
  }
  return true;
}

// Tello state string: a string that parses is written back by the emulator's formatter to a string
// that parses too, and writing that one again changes nothing.
inline bool tello_state_target(std::span<const std::uint8_t> data) {
  using namespace tello;
  TelloState state, again;
  const auto result = TelloStateParser().parse(data, state);
  if (!result.ok()) return !result.detail.empty();
  std::string text, text_again;
  format_tello_state(state, text);
  if (!TelloStateParser().parse(text, again).ok()) return false;
  format_tello_state(again, text_again);
  return text == text_again && again.has_mission_pad == state.has_mission_pad;
}

// Tello video: datagrams cut from the input (sizes from its first byte) into access units: every byte
// comes out in a unit, as junk, or stays buffered (unless a unit overflowed), each unit within the
// limit and starting with a start code.
inline bool tello_video_target(std::span<const std::uint8_t> data) {
  using namespace tello;
  if (data.empty()) return true;
  const std::size_t step = 1 + data[0] % 251;
  const auto stream = data.subspan(1);
  constexpr std::size_t kLimit = 16 * 1024;
  std::size_t unit_bytes = 0;
  bool units_ok = true;
  AnnexBAssembler assembler(
      [&](std::span<const std::uint8_t> u) {
        unit_bytes += u.size();
        units_ok = units_ok && u.size() <= kLimit && u.size() >= 3 && u[0] == 0 && u[1] == 0;
      },
      kLimit, 64);
  std::size_t junk = 0;
  bool overflow = false;
  for (std::size_t pos = 0; pos < stream.size(); pos += step) {
    const auto report = assembler.feed(stream.subspan(pos, std::min(step, stream.size() - pos)));
    junk += report.junk_bytes;
    overflow = overflow || report.overflow;
    if (assembler.buffered_bytes() > kLimit) return false;
  }
  return units_ok && (overflow || unit_bytes + junk + assembler.buffered_bytes() == stream.size());
}

// Tello replies and rc arguments: classified or refused, never read past the input.
inline bool tello_reply_target(std::span<const std::uint8_t> data) {
  using namespace tello;
  TelloReply reply;
  const ReplyError error = parse_reply(data, reply);
  if (error == ReplyError::None && (reply.text.empty() || reply.text.size() > kMaxReplyBytes)) return false;
  RcSticks sticks;
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  if (parse_rc_arguments(text, sticks)) {
    for (int v : {sticks.a, sticks.b, sticks.c, sticks.d})
      if (v < -kMaxStick || v > kMaxStick) return false;
  }
  return true;
}

}  // namespace labo::fuzz
