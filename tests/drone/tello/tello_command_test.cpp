// The Tello's command channel without sockets: one command in flight, replies matched in order,
// timeouts and resends only of commands that may be repeated, emergency first, replies to nothing.
#include <catch2/catch.hpp>
#include <string>

#include "drone/tello/tello_command.hpp"

using namespace labo;
using namespace labo::tello;
using Result = CommandOutcome::Result;

namespace {

std::span<const std::uint8_t> bytes(std::string_view s) { return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}; }

TelloReply reply_of(std::string_view text) {
  TelloReply r;
  REQUIRE(parse_reply(bytes(text), r) == ReplyError::None);
  return r;
}

std::string sent(const TelloCommandChannel::Tick& tick) { return tick.send ? std::string(*tick.send) : ""; }

}  // namespace

TEST_CASE("tello: replies are ok, error or a value, and junk replies are refused", "[tello][command]") {
  CHECK(reply_of("ok").kind == ReplyKind::Ok);
  CHECK(reply_of("OK\r\n").kind == ReplyKind::Ok);
  CHECK(reply_of("error").kind == ReplyKind::Error);
  CHECK(reply_of("error Motor stop").kind == ReplyKind::Error);
  CHECK(reply_of("error Motor stop").text == "error Motor stop");
  CHECK(reply_of("87\r\n").kind == ReplyKind::Value);
  CHECK(reply_of("87\r\n").text == "87");
  CHECK(reply_of("okay").kind == ReplyKind::Value);
  TelloReply r;
  CHECK(parse_reply(bytes(""), r) == ReplyError::Empty);
  CHECK(parse_reply(bytes("\r\n"), r) == ReplyError::Empty);
  CHECK(parse_reply(bytes(std::string(65, 'a')), r) == ReplyError::TooLong);
  CHECK(parse_reply(bytes(std::string("o\0k", 3)), r) == ReplyError::NotText);
  CHECK(to_string(ReplyError::NotText) == "tello_reply_not_text");
}

TEST_CASE("tello: one command in flight, the next sent when the reply comes", "[tello][command]") {
  TelloCommandChannel channel({.reply_timeout_s = 1.0, .motion_timeout_s = 10.0, .retries = 2});
  REQUIRE(channel.push("command"));
  REQUIRE(channel.push("streamon"));
  REQUIRE(channel.push("battery?"));
  CHECK_FALSE(channel.push("rc 0 0 0 0"));  // streamed, never queued
  CHECK_FALSE(channel.push(""));
  CHECK_FALSE(channel.push(std::string(65, 'a')));
  CHECK(sent(channel.tick(0.0)) == "command");
  CHECK(sent(channel.tick(0.1)).empty());  // waits for the reply
  CHECK(channel.in_flight() == std::optional<std::string_view>("command"));
  auto o = channel.reply(reply_of("ok"), 0.2);
  REQUIRE(o);
  CHECK(o->result == Result::Ok);
  CHECK(o->command == "command");
  CHECK(o->attempts == 1);
  CHECK(sent(channel.tick(0.2)) == "streamon");
  o = channel.reply(reply_of("error"), 0.3);
  REQUIRE(o);
  CHECK(o->result == Result::Error);
  CHECK(sent(channel.tick(0.3)) == "battery?");
  o = channel.reply(reply_of("87"), 0.35);
  REQUIRE(o);
  CHECK(o->result == Result::Value);
  CHECK(o->reply == "87");
  CHECK(channel.idle());
  // A reply while nothing waits is the caller's to count: the channel says there is no command.
  CHECK_FALSE(channel.reply(reply_of("ok"), 0.4));

  for (std::size_t i = 0; i < kMaxQueuedCommands; ++i) REQUIRE(channel.push("battery?"));
  CHECK_FALSE(channel.push("battery?"));  // the queue is bounded
}

TEST_CASE("tello: a late reply makes repeatable commands resend, never a move or a take-off", "[tello][command]") {
  TelloCommandChannel channel({.reply_timeout_s = 1.0, .motion_timeout_s = 10.0, .retries = 2});
  REQUIRE(channel.push("command"));
  CHECK(sent(channel.tick(0.0)) == "command");
  CHECK(sent(channel.tick(0.99)).empty());
  CHECK(sent(channel.tick(1.0)) == "command");  // resend 1
  CHECK(sent(channel.tick(2.0)) == "command");  // resend 2
  auto tick = channel.tick(3.0);
  REQUIRE(tick.finished);
  CHECK(tick.finished->result == Result::TimedOut);
  CHECK(tick.finished->attempts == 3);
  CHECK(tick.finished->sent_t == 0.0);
  CHECK(channel.idle());

  // A take-off is answered once done: its longer timeout, then given up, never sent twice.
  REQUIRE(channel.push("takeoff"));
  REQUIRE(channel.push("forward 50"));
  CHECK(sent(channel.tick(10.0)) == "takeoff");
  CHECK(sent(channel.tick(15.0)).empty());
  tick = channel.tick(20.0);
  REQUIRE(tick.finished);
  CHECK(tick.finished->command == "takeoff");
  CHECK(tick.finished->result == Result::TimedOut);
  CHECK(sent(tick) == "forward 50");  // the next goes out in the same tick
  tick = channel.tick(30.0);
  REQUIRE(tick.finished);
  CHECK(tick.finished->attempts == 1);

  // A landing may be repeated: a second "land" cannot fly the drone anywhere.
  REQUIRE(channel.push("land"));
  CHECK(sent(channel.tick(40.0)) == "land");
  CHECK(sent(channel.tick(50.0)) == "land");
}

TEST_CASE("tello: emergency jumps the queue and abandons the command in flight", "[tello][command]") {
  TelloCommandChannel channel;
  REQUIRE(channel.push("takeoff"));
  REQUIRE(channel.push("battery?"));
  CHECK(sent(channel.tick(0.0)) == "takeoff");
  channel.emergency();
  auto tick = channel.tick(0.01);
  REQUIRE(tick.finished);
  CHECK(tick.finished->result == Result::Abandoned);
  CHECK(tick.finished->command == "takeoff");
  CHECK(sent(tick) == "emergency");
  CHECK(channel.queued() == 0);  // the queue went with it
  const auto o = channel.reply(reply_of("ok"), 0.02);
  REQUIRE(o);
  CHECK(o->command == "emergency");
  CHECK(command_class("emergency") == CommandClass::Emergency);
  CHECK(command_class("cw 90") == CommandClass::Motion);
  CHECK(command_class("speed 50") == CommandClass::Setup);
  CHECK(command_class("battery?") == CommandClass::Setup);

  // The link is lost: everything goes, without outcomes.
  REQUIRE(channel.push("command"));
  CHECK(sent(channel.tick(1.0)) == "command");
  channel.reset();
  CHECK(channel.idle());
  CHECK_FALSE(channel.tick(5.0).finished);
}
