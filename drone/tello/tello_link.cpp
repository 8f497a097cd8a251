#include "drone/tello/tello_link.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "core/config_reader.hpp"

namespace labo::tello {

using ardrone2::Endpoint;
using ardrone2::Socket;
using replay::RecordChannel;
using replay::RecordingWriter;
using replay::kNoteTelloGaveUpPrefix;
using replay::kNoteVideoConnected;

using namespace tello;

namespace {
constexpr int kVideoReceiveBufferBytes = 2 << 20;  // an IDR arrives as a burst of ~100 datagrams
constexpr Seconds kMaxReplyWaitS = 0.01;
constexpr int kMinSpeedCmps = 10, kMaxSpeedCmps = 100;

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}
}  // namespace

TelloLinkSettings read_tello_link_settings(const ConfigReader& c) {
  TelloLinkSettings s;
  s.host = c.string_or("host", s.host);
  s.command_port = c.integer_or("command_port", s.command_port, 1, 65535);
  s.state_port = c.integer_or("state_port", s.state_port, 0, 65535);
  s.video_port = c.integer_or("video_port", s.video_port, 0, 65535);
  s.reply_timeout_s = c.number_or("reply_timeout_s", s.reply_timeout_s, Range::closed(0.05, 10.0));
  s.motion_timeout_s = c.number_or("motion_timeout_s", s.motion_timeout_s, Range::closed(1.0, 60.0));
  s.command_retries = c.integer_or("command_retries", s.command_retries, 0, 10);
  // At most 10 s: well inside the 15 s after which a Tello without commands lands.
  s.rc_interval_s = c.number_or("rc_interval_s", s.rc_interval_s, Range::closed(0.01, 10.0));
  s.rc_limit_percent = c.integer_or("rc_limit_percent", s.rc_limit_percent, 1, kMaxStick);
  s.degraded_after_s = c.number_or("degraded_after_s", s.degraded_after_s, Range::closed(0.05, 10.0));
  s.lost_after_s = c.number_or("lost_after_s", s.lost_after_s, Range::closed(0.1, 60.0));
  s.video = c.boolean_or("video", s.video);
  s.downvision = c.boolean_or("downvision", s.downvision);
  const std::string rec = c.string_or("recording", "");
  if (!rec.empty()) s.recording = rec;
  if (s.lost_after_s <= s.degraded_after_s) c.fail("lost_after_s", "must be greater than degraded_after_s");
  c.finish();
  return s;
}

TelloLink::TelloLink(TelloLinkSettings settings, Logger logger, const Clock* clock)
    : settings_(std::move(settings)), logger_(std::move(logger)), clock_(clock ? clock : &own_clock_),
      counters_(logger_), status_(logger_, counters_),
      channel_(TelloCommandTiming{settings_.reply_timeout_s, settings_.motion_timeout_s, settings_.command_retries}),
      camera_switch_(settings_.downvision) {
  datagram_.reserve(kMaxCommandBytes);
  state_receiver_ = std::make_unique<TelloStateReceiver>(counters_, [this](const NavdataSample& s, const TelloState&) {
    last_state_t_ = s.t;
    std::lock_guard lock(listener_mutex_);
    if (listener_) listener_->on_navdata(s);
  });
  video_receiver_ = std::make_unique<TelloVideoReceiver>(
      counters_,
      [this](const VideoFrame& f) {
        std::lock_guard lock(listener_mutex_);
        if (listener_) listener_->on_video(f);
      },
      [this](const EncodedVideo& unit) {
        std::lock_guard lock(listener_mutex_);
        if (listener_) listener_->on_encoded_video(unit);
      });
}

TelloLink::~TelloLink() { stop(); }

void TelloLink::open() {
  if (command_socket_.valid()) return;
  command_endpoint_ = Endpoint::resolve(settings_.host, settings_.command_port);
  command_socket_ = Socket::udp(0);
  state_socket_ = Socket::udp(settings_.state_port);
  video_socket_ = Socket::udp(settings_.video_port);
  ::setsockopt(video_socket_.fd(), SOL_SOCKET, SO_RCVBUF, &kVideoReceiveBufferBytes, sizeof(kVideoReceiveBufferBytes));
}

void TelloLink::start() {
  if (running_) return;
  open();
  if (!settings_.recording.empty()) recorder_ = std::make_unique<RecordingWriter>(settings_.recording);
  enter_sdk_mode();
  running_ = true;
  set_state(LinkState::Connecting, clock_->now());
  control_thread_ = std::thread([this] { control_loop(); });
  state_thread_ = std::thread([this] { state_loop(); });
  video_thread_ = std::thread([this] { video_loop(); });
}

void TelloLink::stop() {
  if (!running_.exchange(false)) return;
  for (auto* t : {&control_thread_, &state_thread_, &video_thread_})
    if (t->joinable()) t->join();
  set_state(LinkState::Disconnected, clock_->now());
  if (recorder_) recorder_->flush();
}

void TelloLink::set_listener(DroneLinkListener* listener) {
  std::lock_guard lock(listener_mutex_);
  listener_ = listener;
}

void TelloLink::takeoff() { send_command("takeoff"); }

void TelloLink::land() {
  std::lock_guard lock(command_mutex_);
  sticks_ = RcSticks{};
  if (!channel_.push("land")) counters_.add("tello_command_queue_full");
}

void TelloLink::emergency() {
  std::lock_guard lock(command_mutex_);
  sticks_ = RcSticks{};
  channel_.emergency();
}

void TelloLink::flat_trim() {
  // The SDK has no flat trim: the Tello levels its IMU itself. Take-offs ask for one every time.
  counters_.add("tello_flat_trim_not_in_sdk");
}

void TelloLink::move(const MoveCommand& command) {
  std::lock_guard lock(command_mutex_);
  sticks_ = rc_from_move(command, settings_.rc_limit_percent);
}

void TelloLink::hover() {
  std::lock_guard lock(command_mutex_);
  sticks_ = RcSticks{};
}

void TelloLink::select_camera(CameraId camera) {
  TelloCameraSwitch::Decision decision;
  {
    std::lock_guard lock(command_mutex_);
    decision = camera_switch_.select(camera);
    if (decision.command && !channel_.push(*decision.command)) counters_.add("tello_command_queue_full");
  }
  if (decision.unavailable)
    refuse_bottom_camera(clock_->now(), settings_.downvision ? "the drone refused downvision (not a Tello EDU)"
                                                             : "tello.link.downvision is off");
}

// The documented fallback (docs/tello.md "Landing without a bottom camera"): counted, logged at most
// once a second, frames stay front.
void TelloLink::refuse_bottom_camera(Seconds t, std::string_view why) {
  counters_.add("tello_bottom_camera_unavailable");
  std::size_t suppressed = 0;
  if (refusals_.allow("bottom_camera", t, &suppressed)) {
    logger_.warn(t, "bottom camera refused: the Tello streams its front camera only; frames stay front")
        .kv("why", why)
        .kv("suppressed", suppressed);
  }
}

void TelloLink::set_config(const std::string& key, const std::string& value) {
  int speed = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), speed);
  if (key != "speed" || ec != std::errc() || end != value.data() + value.size() || speed < kMinSpeedCmps ||
      speed > kMaxSpeedCmps)
    throw std::invalid_argument("Tello config: the one key is 'speed' with an integer " + std::to_string(kMinSpeedCmps) +
                                "-" + std::to_string(kMaxSpeedCmps) + " (cm/s), got '" + key + "'='" + value + "'");
  send_command("speed " + value);
}

bool TelloLink::send_command(const std::string& command) {
  std::lock_guard lock(command_mutex_);
  if (channel_.push(command)) return true;
  counters_.add(valid_command_text(command) ? "tello_command_queue_full" : "tello_command_invalid");
  return false;
}

LinkState TelloLink::state() const { return status_.state(); }

LinkStatistics TelloLink::statistics() const { return counters_.snapshot(); }

void TelloLink::enter_sdk_mode() {
  std::lock_guard lock(command_mutex_);
  channel_.reset();
  sdk_mode_ = false;
  channel_.push("command");
}

void TelloLink::record(RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes) {
  if (recorder_) recorder_->write(channel, t, bytes);
}

void TelloLink::set_state(LinkState s, Seconds t) {
  status_.set(s, t, recorder_.get(), [this](LinkState state, Seconds when) {
    std::lock_guard lock(listener_mutex_);
    if (listener_) listener_->on_link_state(state, when);
  });
}

// ---- control thread ----------------------------------------------------------------------------

void TelloLink::control_loop() {
  Seconds next_sticks = clock_->now();
  while (running_) {
    Seconds t = clock_->now();
    supervise(t);
    send_command_tick(t);
    if (t >= next_sticks) {
      send_sticks(t);
      next_sticks = std::max(next_sticks + settings_.rc_interval_s, t);
    }
    status_.update_rates(t, "state_packets");
    t = clock_->now();
    receive_replies(std::clamp(next_sticks - t, 0.0, kMaxReplyWaitS));
  }
}

void TelloLink::send_datagram(RecordChannel channel, std::string_view text, Seconds t) {
  const auto bytes = bytes_of(text);
  if (command_socket_.send_to(bytes, command_endpoint_)) {
    counters_.add(channel == RecordChannel::TelloCommandOut && text.starts_with("rc ") ? "rc_sent" : "commands_sent");
  } else {
    counters_.add("command_send_failed");
  }
  record(channel, t, bytes);
}

void TelloLink::send_command_tick(Seconds t) {
  std::optional<CommandOutcome> finished;
  bool sent = false;
  {
    std::lock_guard lock(command_mutex_);
    const TelloCommandChannel::Tick tick = channel_.tick(t);
    finished = tick.finished;
    if (tick.send) {
      datagram_.assign(*tick.send);
      sent = true;
    }
  }
  std::lock_guard session(session_mutex_);
  if (finished) finish(*finished, t);
  if (!sent) return;
  state_receiver_->command_sent(datagram_, t);
  send_datagram(RecordChannel::TelloCommandOut, datagram_, t);
}

void TelloLink::send_sticks(Seconds t) {
  RcSticks sticks;
  {
    std::lock_guard lock(command_mutex_);
    if (!sdk_mode_) return;
    sticks = sticks_;
  }
  format_rc(sticks, datagram_);
  std::lock_guard session(session_mutex_);
  state_receiver_->sticks(sticks.centred());
  send_datagram(RecordChannel::TelloCommandOut, datagram_, t);
}

void TelloLink::receive_replies(Seconds wait_s) {
  std::array<std::uint8_t, 2048> buffer;
  Endpoint from;
  const long n = command_socket_.receive_from(buffer, from, wait_s);
  if (n < 0) return;
  const Seconds t = clock_->now();
  if (static_cast<std::size_t>(n) > buffer.size()) {
    counters_.bad_input("tello_reply_too_long", t, std::to_string(n) + " bytes");
    return;
  }
  if (!from_drone(from, t, "tello_reply_foreign_sender")) return;
  const auto bytes = std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n));
  std::lock_guard session(session_mutex_);
  record(RecordChannel::TelloReplyIn, t, bytes);
  counters_.add("replies");
  TelloReply reply;
  if (const ReplyError error = parse_reply(bytes, reply); error != ReplyError::None) {
    counters_.bad_input(to_string(error), t, "reply of " + std::to_string(n) + " bytes refused");
    return;
  }
  std::optional<CommandOutcome> outcome;
  {
    std::lock_guard lock(command_mutex_);
    outcome = channel_.reply(reply, t);
  }
  if (!outcome) {
    std::string detail(reply.text);  // (not "'" + std::string: GCC 12 warns falsely, -Wrestrict)
    detail.append(" came while no command waits");
    counters_.bad_input("tello_reply_unsolicited", t, detail);
    return;
  }
  finish(*outcome, t);
}

// A command ended: the flight phase learns it, SDK mode starts the video, failures are counted.
// Called with session_mutex_ held.
void TelloLink::finish(const CommandOutcome& o, Seconds t) {
  using Result = CommandOutcome::Result;
  state_receiver_->command_finished(o, t);
  if (o.result == Result::TimedOut || o.result == Result::Abandoned) {
    counters_.add(o.result == Result::TimedOut ? "tello_command_timed_out" : "tello_command_abandoned");
    if (recorder_) recorder_->note(t, std::string(kNoteTelloGaveUpPrefix) + std::string(to_string(o.result)) + " " + o.command);
    logger_.warn(t, "Tello command without reply").kv("command", o.command).kv("result", to_string(o.result))
        .kv("attempts", o.attempts);
  } else if (o.result == Result::Error || (o.result == Result::Value && !o.command.ends_with("?"))) {
    counters_.add("tello_command_refused");
    logger_.warn(t, "Tello refused a command").kv("command", o.command).kv("reply", o.reply);
  } else {
    counters_.add("tello_command_ok");
  }
  std::lock_guard lock(command_mutex_);
  if (camera_switch_.finished(o)) {
    counters_.add("tello_downvision_refused");
    logger_.warn(t, "the Tello has no downward camera: the platform stage lands at the estimated base")
        .kv("command", o.command).kv("result", to_string(o.result)).kv("reply", o.reply);
  }
  if (o.command != "command") return;
  if (o.result == Result::Ok) {
    sdk_mode_ = true;
    if (settings_.video) channel_.push("streamon");
    if (const auto down = camera_switch_.after_sdk_mode(); down && settings_.video) channel_.push(*down);
    reset_video_ = true;
  } else if (!sdk_mode_) {
    channel_.push("command");  // keep knocking until the drone answers
  }
}

void TelloLink::supervise(Seconds t) {
  const LinkState s = state_after_silence(last_state_t_.load(), t, settings_.degraded_after_s, settings_.lost_after_s);
  if (s == LinkState::Lost && state() != LinkState::Lost) {
    // The drone went silent: enter SDK mode again (and restart the video) once it answers. A Tello
    // that stays without commands for 15 s lands by itself meanwhile.
    counters_.add("reconnects");
    enter_sdk_mode();
  }
  set_state(s, t);
}

bool TelloLink::from_drone(const Endpoint& from, Seconds t, std::string_view kind) {
  if (from.addr.sin_addr.s_addr == command_endpoint_.addr.sin_addr.s_addr) return true;
  counters_.bad_input(kind, t, "datagram from another host");
  return false;
}

// ---- state and video threads -------------------------------------------------------------------

void TelloLink::state_loop() {
  std::vector<std::uint8_t> buffer(4096);
  Endpoint from;
  while (running_) {
    const long n = state_socket_.receive_from(buffer, from, 0.05);
    if (n < 0) continue;
    const Seconds t = clock_->now();
    if (static_cast<std::size_t>(n) > buffer.size()) {
      counters_.bad_input("tello_state_too_long", t, std::to_string(n) + " bytes");
      continue;
    }
    if (!from_drone(from, t, "tello_state_foreign_sender")) continue;
    const auto bytes = std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n));
    std::lock_guard session(session_mutex_);
    record(RecordChannel::TelloStateIn, t, bytes);
    state_receiver_->datagram(bytes, t);
  }
}

void TelloLink::video_loop() {
  std::vector<std::uint8_t> buffer(65536);
  Endpoint from;
  while (running_) {
    if (reset_video_.exchange(false)) {
      video_receiver_->reset();
      if (recorder_) recorder_->note(clock_->now(), kNoteVideoConnected);
    }
    const long n = video_socket_.receive_from(buffer, from, 0.05);
    if (n < 0) continue;
    const Seconds t = clock_->now();
    if (static_cast<std::size_t>(n) > buffer.size()) {
      counters_.bad_input("tello_video_datagram_too_large", t, std::to_string(n) + " bytes");
      continue;
    }
    if (!from_drone(from, t, "tello_video_foreign_sender")) continue;
    const auto bytes = std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n));
    record(RecordChannel::TelloVideoIn, t, bytes);
    video_receiver_->datagram(bytes, t);
  }
}

}  // namespace labo::tello
