#pragma once
// The Tello's text commands on UDP 8889 (SDK 2.0): one command in flight at a time, each answered
// by "ok", "error ..." or a value (read commands), in the order sent and without any id. A motion
// command (takeoff, land, up 50, cw 90, ...) is answered when the drone has done it. "rc a b c d"
// gets no answer and is not sent through this channel (TelloLink streams it).
//
// TelloCommandChannel holds the queue and the command in flight, without any I/O: tick() says what
// to send now (the next command, or a resend of one whose reply is late), reply() completes the
// command in flight. Commands that can be repeated without harm (command, streamon, reads, emergency,
// land) are resent up to `retries` times; the others are never resent (a second "forward 50" would
// fly another 50 cm). "emergency" jumps the queue and abandons the command in flight.
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/time.hpp"

namespace labo::tello {

inline constexpr std::size_t kMaxCommandBytes = 64;  // longest SDK 2.0 command: "curve" with 7 numbers
inline constexpr std::size_t kMaxReplyBytes = 64;
inline constexpr std::size_t kMaxQueuedCommands = 8;

enum class ReplyKind { Ok, Error, Value };

struct TelloReply {
  ReplyKind kind = ReplyKind::Ok;
  std::string_view text;  // the datagram's text without a final line break; valid during the call
};

enum class ReplyError { None, Empty, TooLong, NotText };
std::string_view to_string(ReplyError error);  // counter kind, e.g. "tello_reply_not_text"

// A reply datagram: "ok", "error" or "error <reason>" (any case), anything else a value.
ReplyError parse_reply(std::span<const std::uint8_t> datagram, TelloReply& reply);

// How a command is treated: its reply timeout and whether it may be resent.
enum class CommandClass { Setup, Motion, Emergency };
CommandClass command_class(std::string_view command);

// A command's text: 1-64 printable ASCII characters, no "rc" (streamed, never answered).
bool valid_command_text(std::string_view text);

struct TelloCommandTiming {
  Seconds reply_timeout_s = 1.0;   // command, streamon/streamoff, reads, settings, emergency
  Seconds motion_timeout_s = 10.0; // takeoff, land, moves: answered once done (a take-off takes ~5 s)
  int retries = 2;                 // resends of a command that may be repeated
};

struct CommandOutcome {
  enum class Result { Ok, Error, Value, TimedOut, Abandoned };
  Result result = Result::Ok;
  std::string command;
  std::string reply;   // empty for TimedOut and Abandoned
  Seconds sent_t = 0;  // first send
  Seconds t = 0;       // reply or give-up time
  int attempts = 0;
};
std::string_view to_string(CommandOutcome::Result result);
// What a reply of this kind says of the command it answers.
CommandOutcome::Result result_of(ReplyKind kind);

class TelloCommandChannel {
 public:
  explicit TelloCommandChannel(TelloCommandTiming timing = {});

  // Queues a command; false when it is not valid_command_text() or the queue holds kMaxQueuedCommands.
  bool push(std::string_view command);
  // "emergency" before anything else: the queue is dropped and the command in flight abandoned
  // (reported by the next tick()).
  void emergency();
  // At time t: `send` is the datagram to send now, if any; `finished` a command that ended without
  // its reply (timed out or abandoned).
  struct Tick {
    std::optional<std::string_view> send;  // valid until the next call
    std::optional<CommandOutcome> finished;
  };
  Tick tick(Seconds t);
  // A reply completes the command in flight; empty when no command is in flight (a reply to nothing).
  std::optional<CommandOutcome> reply(const TelloReply& reply, Seconds t);
  // The link was lost: the queue and the command in flight are dropped without outcomes.
  void reset();

  bool idle() const { return !in_flight_ && queue_.empty(); }
  std::optional<std::string_view> in_flight() const;
  std::size_t queued() const { return queue_.size(); }

 private:
  struct InFlight {
    std::string command;
    CommandClass kind = CommandClass::Setup;
    Seconds first_sent = 0, last_sent = 0;
    int attempts = 0;
  };
  Seconds timeout_of(CommandClass kind) const;
  int retries_of(CommandClass kind) const;

  TelloCommandTiming timing_;
  std::deque<std::string> queue_;
  std::optional<InFlight> in_flight_;
  std::optional<CommandOutcome> abandoned_;
};

}  // namespace labo::tello
