#include "drone/tello/tello_command.hpp"

#include <algorithm>
#include <array>
#include <cctype>

namespace labo::tello {

namespace {

constexpr std::array<std::string_view, 15> kMotionWords = {"takeoff", "land", "up",   "down", "left",
                                                           "right",   "forward", "back", "cw", "ccw",
                                                           "flip",    "go",   "curve", "jump", "stop"};

std::string_view first_word(std::string_view text) { return text.substr(0, text.find(' ')); }

bool printable(std::string_view text) {
  return std::all_of(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) <= 0x7E;
  });
}

bool starts_with_nocase(std::string_view text, std::string_view prefix) {
  if (text.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != prefix[i]) return false;
  return true;
}

// Resending these cannot fly the drone further than asked.
bool may_resend(CommandClass kind, std::string_view command) {
  return kind != CommandClass::Motion || command == "land" || command == "stop";
}

}  // namespace

std::string_view to_string(ReplyError error) {
  switch (error) {
    case ReplyError::None: return "tello_reply_ok";
    case ReplyError::Empty: return "tello_reply_empty";
    case ReplyError::TooLong: return "tello_reply_too_long";
    case ReplyError::NotText: return "tello_reply_not_text";
  }
  return "tello_reply_error";
}

std::string_view to_string(CommandOutcome::Result result) {
  switch (result) {
    case CommandOutcome::Result::Ok: return "ok";
    case CommandOutcome::Result::Error: return "error";
    case CommandOutcome::Result::Value: return "value";
    case CommandOutcome::Result::TimedOut: return "timed_out";
    case CommandOutcome::Result::Abandoned: return "abandoned";
  }
  return "?";
}

CommandOutcome::Result result_of(ReplyKind kind) {
  switch (kind) {
    case ReplyKind::Ok: return CommandOutcome::Result::Ok;
    case ReplyKind::Error: return CommandOutcome::Result::Error;
    case ReplyKind::Value: return CommandOutcome::Result::Value;
  }
  return CommandOutcome::Result::Error;
}

ReplyError parse_reply(std::span<const std::uint8_t> datagram, TelloReply& reply) {
  std::string_view text(reinterpret_cast<const char*>(datagram.data()), datagram.size());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
  if (text.empty()) return ReplyError::Empty;
  if (text.size() > kMaxReplyBytes) return ReplyError::TooLong;
  if (!printable(text)) return ReplyError::NotText;
  reply.text = text;
  if (text.size() == 2 && starts_with_nocase(text, "ok")) {
    reply.kind = ReplyKind::Ok;
  } else if (starts_with_nocase(text, "error")) {
    reply.kind = ReplyKind::Error;
  } else {
    reply.kind = ReplyKind::Value;
  }
  return ReplyError::None;
}

CommandClass command_class(std::string_view command) {
  const std::string_view word = first_word(command);
  if (word == "emergency") return CommandClass::Emergency;
  for (std::string_view m : kMotionWords)
    if (word == m) return CommandClass::Motion;
  return CommandClass::Setup;
}

bool valid_command_text(std::string_view text) {
  return !text.empty() && text.size() <= kMaxCommandBytes && printable(text) && first_word(text) != "rc";
}

TelloCommandChannel::TelloCommandChannel(TelloCommandTiming timing) : timing_(timing) {}

Seconds TelloCommandChannel::timeout_of(CommandClass kind) const {
  return kind == CommandClass::Motion ? timing_.motion_timeout_s : timing_.reply_timeout_s;
}

int TelloCommandChannel::retries_of(CommandClass kind) const {
  return in_flight_ && may_resend(kind, in_flight_->command) ? timing_.retries : 0;
}

bool TelloCommandChannel::push(std::string_view command) {
  if (!valid_command_text(command) || queue_.size() >= kMaxQueuedCommands) return false;
  queue_.emplace_back(command);
  return true;
}

void TelloCommandChannel::emergency() {
  queue_.clear();
  if (in_flight_ && in_flight_->kind != CommandClass::Emergency) {
    abandoned_ = CommandOutcome{CommandOutcome::Result::Abandoned, in_flight_->command, "", in_flight_->first_sent,
                                in_flight_->last_sent, in_flight_->attempts};
  }
  in_flight_.reset();
  queue_.emplace_front("emergency");
}

TelloCommandChannel::Tick TelloCommandChannel::tick(Seconds t) {
  Tick tick;
  if (abandoned_) {
    tick.finished = std::move(abandoned_);
    abandoned_.reset();
  }
  if (in_flight_ && t - in_flight_->last_sent >= timeout_of(in_flight_->kind)) {
    if (in_flight_->attempts <= retries_of(in_flight_->kind)) {
      ++in_flight_->attempts;
      in_flight_->last_sent = t;
      tick.send = in_flight_->command;
      return tick;
    }
    tick.finished = CommandOutcome{CommandOutcome::Result::TimedOut, std::move(in_flight_->command), "",
                                   in_flight_->first_sent, t, in_flight_->attempts};
    in_flight_.reset();
  }
  if (!in_flight_ && !queue_.empty()) {
    InFlight next;
    next.command = std::move(queue_.front());
    queue_.pop_front();
    next.kind = command_class(next.command);
    next.first_sent = next.last_sent = t;
    next.attempts = 1;
    in_flight_ = std::move(next);
    tick.send = in_flight_->command;
  }
  return tick;
}

std::optional<CommandOutcome> TelloCommandChannel::reply(const TelloReply& reply, Seconds t) {
  if (!in_flight_) return std::nullopt;
  CommandOutcome outcome{result_of(reply.kind), std::move(in_flight_->command), std::string(reply.text), in_flight_->first_sent, t,
                         in_flight_->attempts};
  in_flight_.reset();
  return outcome;
}

void TelloCommandChannel::reset() {
  queue_.clear();
  in_flight_.reset();
  abandoned_.reset();
}

std::optional<std::string_view> TelloCommandChannel::in_flight() const {
  if (!in_flight_) return std::nullopt;
  return std::string_view(in_flight_->command);
}

}  // namespace labo::tello
