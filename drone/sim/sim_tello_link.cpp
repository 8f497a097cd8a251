#include "drone/sim/sim_tello_link.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <span>
#include <stdexcept>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_config.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo::sim {

using tello::TelloConfig;

using namespace tello;

namespace {

// The driver's control loop and the drone's firmware look at their inputs this often (TelloLink's
// control thread waits at most 10 ms for a reply between two looks).
constexpr Seconds kTickS = 0.01;
constexpr int kMinSpeedCmps = 10, kMaxSpeedCmps = 100;

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// The lockstep link logs nothing (a campaign's runs would drown in it); every event is counted.
Logger quiet_logger() { return Logger("sim_tello", LogLevel::Off); }

}  // namespace

SimTelloSettings sim_tello_settings(const TelloConfig& tello) {
  SimTelloSettings s;
  s.state_rate_hz = tello.emulator.state_rate_hz;
  s.firmware = tello.emulator.firmware;
  s.timing = {.reply_timeout_s = tello.link.reply_timeout_s,
              .motion_timeout_s = tello.link.motion_timeout_s,
              .retries = tello.link.command_retries};
  s.rc_interval_s = tello.link.rc_interval_s;
  s.rc_limit_percent = tello.link.rc_limit_percent;
  s.degraded_after_s = tello.link.degraded_after_s;
  s.lost_after_s = tello.link.lost_after_s;
  s.video = tello.link.video;
  s.downvision = tello.link.downvision;
  s.video_gop = tello.emulator.video_gop;
  s.video_bitrate_kbps = tello.emulator.video_bitrate_kbps;
  return s;
}

struct SimTelloLink::VideoEncoder {
  ardrone2::H264Encoder encoder;
  ardrone2::EncodedFrame encoded;
  explicit VideoEncoder(const ardrone2::H264EncoderSettings& s) : encoder(s) {}
};

SimTelloLink::SimTelloLink(SimulatedLab& lab, const SimLinkSettings& link, const SimTelloSettings& tello)
    : lab_(lab),
      link_(link),
      tello_(tello),
      rng_(link.seed ^ 0x7e110c0ffeeULL),
      now_(lab.now()),
      counters_(quiet_logger()),
      channel_(tello.timing),
      camera_switch_(tello.downvision),
      drone_counters_(quiet_logger()),
      firmware_(tello.firmware, drone_counters_) {
  if (!(tello_.state_rate_hz > 0) || !(link_.video_fps > 0) || !(tello_.rc_interval_s > 0))
    throw std::invalid_argument("SimTelloLink: the state rate, the video rate and the rc interval must be positive");
  state_receiver_ = std::make_unique<TelloStateReceiver>(counters_, [this](const NavdataSample& s, const TelloState&) {
    last_state_arrival_ = s.t;
    if (listener_) listener_->on_navdata(s);
  });
  video_receiver_ = std::make_unique<TelloVideoReceiver>(counters_, [this](const VideoFrame& f) {
    if (listener_) listener_->on_video(f);
  });
  datagram_.reserve(kMaxCommandBytes);
  state_text_.reserve(kMaxStateBytes);
  next_driver_ = next_sticks_ = next_state_ = next_frame_ = now_;
  last_to_drone_ = last_reply_ = last_state_ = last_video_ = now_;
  enter_sdk_mode();
}

SimTelloLink::~SimTelloLink() = default;

// ---- the driver's commands (TelloLink's behaviour) ----------------------------------------------

void SimTelloLink::push(std::string_view command) {
  if (!channel_.push(command)) counters_.add(valid_command_text(command) ? "tello_command_queue_full" : "tello_command_invalid");
}

void SimTelloLink::land() {
  sticks_ = RcSticks{};
  push("land");
}

void SimTelloLink::emergency() {
  sticks_ = RcSticks{};
  channel_.emergency();
}

void SimTelloLink::move(const MoveCommand& command) { sticks_ = rc_from_move(command, tello_.rc_limit_percent); }

void SimTelloLink::select_camera(CameraId camera) {
  const TelloCameraSwitch::Decision decision = camera_switch_.select(camera);
  if (decision.command) push(*decision.command);
  if (decision.unavailable) counters_.add("tello_bottom_camera_unavailable");
}

void SimTelloLink::set_config(const std::string& key, const std::string& value) {
  int speed = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), speed);
  if (key != "speed" || ec != std::errc() || end != value.data() + value.size() || speed < kMinSpeedCmps ||
      speed > kMaxSpeedCmps)
    throw std::invalid_argument("Tello config: the one key is 'speed' with an integer 10-100 (cm/s), got '" + key +
                                "'='" + value + "'");
  push("speed " + value);
}

LinkStatistics SimTelloLink::statistics() const {
  LinkStatistics s = counters_.snapshot();
  if (now_ > 0) {
    s.navdata_rate_hz = static_cast<double>(counters_.get("state_packets")) / now_;
    // Without H.264 each delivered frame is counted as it reaches the listener; with it, each frame
    // TelloVideoReceiver decodes (its "video_frames" counts access units, decodable or not).
    s.video_fps = static_cast<double>(counters_.get(link_.h264 ? "video_decoded" : "video_frames")) / now_;
  }
  return s;
}

void SimTelloLink::enter_sdk_mode() {
  channel_.reset();
  sdk_mode_ = false;
  channel_.push("command");
}

// ---- the lockstep loop -------------------------------------------------------------------------

void SimTelloLink::advance_to(Seconds t) {
  if (state_ == LinkState::Disconnected) {
    state_ = LinkState::Connecting;
    if (listener_) listener_->on_link_state(state_, now_);
  }
  for (;;) {
    const Seconds delivery = queue_.empty() ? t + 1.0 : queue_.top().t;
    const Seconds next = std::min({delivery, next_driver_, next_state_, next_frame_});
    if (next > t) break;
    now_ = next;
    if (delivery == next) {
      const auto d = queue_.pop();
      deliver(d.channel, d.slot, d.t);
    } else if (next_driver_ == next) {
      drone_tick(next);
      driver_tick(next);
      next_driver_ = next + kTickS;
    } else if (next_state_ == next) {
      state_tick(next);
      next_state_ = next + 1.0 / tello_.state_rate_hz;
    } else {
      video_tick(next);
      next_frame_ = next + 1.0 / link_.video_fps;
    }
  }
  now_ = std::max(now_, t);
  lab_.advance_to(now_);
  supervise(now_);
}

// In-order delivery (a channel never overtakes itself), never before it was sent.
Seconds SimTelloLink::arrival(Seconds t, Seconds delay, Seconds& last_arrival) {
  const double jitter = link_.jitter_s > 0 ? link_.jitter_s * normal_(rng_) : 0.0;
  last_arrival = std::max({last_arrival, t, t + delay + jitter});
  return last_arrival;
}

bool SimTelloLink::lost(double probability, Seconds t) {
  return (probability > 0 && uniform_(rng_) < probability) || lab_.link_outage(t);
}

std::size_t SimTelloLink::text_slot(std::string_view text) {
  const std::size_t slot = texts_.acquire();
  texts_.items[slot].assign(text);
  return slot;
}

// TelloLink's control loop: a command to send (or resend, or given up), the sticks every rc interval.
void SimTelloLink::driver_tick(Seconds t) {
  supervise(t);
  const TelloCommandChannel::Tick tick = channel_.tick(t);
  if (tick.finished) finish(*tick.finished, t);
  if (tick.send) {
    datagram_.assign(*tick.send);
    state_receiver_->command_sent(datagram_, t);
    send_to_drone(datagram_, t);
    counters_.add("commands_sent");
  }
  if (t >= next_sticks_) {
    next_sticks_ = std::max(next_sticks_ + tello_.rc_interval_s, t);
    if (!sdk_mode_) return;
    format_rc(sticks_, datagram_);
    state_receiver_->sticks(sticks_.centred());
    send_to_drone(datagram_, t);
    counters_.add("rc_sent");
  }
}

void SimTelloLink::send_to_drone(std::string_view text, Seconds t) {
  if (lost(link_.command_loss, t)) {
    counters_.add("commands_lost");
    return;
  }
  queue_.schedule(arrival(t, link_.command_delay_s, last_to_drone_), Channel::ToDrone, text_slot(text));
}

// The firmware's time: a take-off or landing completes, the watchdog; replies that are due go out.
void SimTelloLink::drone_tick(Seconds t) {
  if (auto reply = firmware_.advance(lab_, t)) pending_replies_.push_back({std::move(reply->text), reply->due_t});
  for (auto it = pending_replies_.begin(); it != pending_replies_.end();) {
    if (it->due_t > t) {
      ++it;
      continue;
    }
    if (lost(link_.command_loss, t)) {
      drone_counters_.add("replies_lost");
    } else {
      queue_.schedule(arrival(t, link_.command_delay_s, last_reply_), Channel::Reply, text_slot(it->text));
    }
    it = pending_replies_.erase(it);
  }
}

void SimTelloLink::state_tick(Seconds t) {
  if (!firmware_.sdk_mode()) return;  // the state goes to whoever sent "command"
  lab_.advance_to(t);
  format_tello_state(firmware_.state(lab_.telemetry()), state_text_);
  if (lost(link_.navdata_loss, t)) {
    drone_counters_.add("state_lost");
    return;
  }
  queue_.schedule(arrival(t, link_.navdata_delay_s, last_state_), Channel::State, text_slot(state_text_));
}

void SimTelloLink::video_tick(Seconds t) {
  if (!firmware_.streaming()) return;
  lab_.advance_to(t);
  if (firmware_.take_stream_restart()) encoder_.reset();  // a new stream starts with an IDR
  if (lab_.video_dropout()) {
    drone_counters_.add("video_dropout");
    return;
  }
  const bool drop = lost(link_.video_loss, t);
  if (drop) drone_counters_.add("video_lost");
  if (!link_.h264) {
    if (drop) return;
    const std::size_t slot = frames_.acquire();
    VideoFrame& f = frames_.items[slot];
    firmware_.render_stream(lab_, f.bgr);
    if (f.bgr.empty()) {
      frames_.release(slot);
      return;
    }
    f.camera = firmware_.down_vision() ? CameraId::Bottom : CameraId::Front;
    f.frame_number = frame_number_++;
    f.t = arrival(t, link_.video_delay_s, last_video_);
    queue_.schedule(f.t, Channel::Video, slot);
    return;
  }
  // H.264: a lost frame is a hole in the stream the decoder sees, as on the wire.
  firmware_.render_stream(lab_, rendered_);
  if (rendered_.empty()) return;
  if (!encoder_) {
    ardrone2::H264EncoderSettings es;
    es.width = rendered_.cols;
    es.height = rendered_.rows;
    es.fps = static_cast<int>(std::lround(link_.video_fps));
    es.gop = tello_.video_gop;
    es.bitrate_kbps = tello_.video_bitrate_kbps;
    encoder_ = std::make_unique<VideoEncoder>(es);
  }
  if (!encoder_->encoder.encode(rendered_, encoder_->encoded)) {
    drone_counters_.add("video_encode_failed");
    return;
  }
  if (drop) return;
  const std::size_t slot = units_.acquire();
  units_.items[slot] = encoder_->encoded.data;
  queue_.schedule(arrival(t, link_.video_delay_s, last_video_), Channel::Video, slot);
}

void SimTelloLink::deliver(Channel channel, std::size_t slot, Seconds t) {
  switch (channel) {
    case Channel::ToDrone: {
      lab_.advance_to(t);
      if (auto reply = firmware_.command(texts_.items[slot], lab_, t))
        pending_replies_.push_back({std::move(reply->text), reply->due_t});
      texts_.release(slot);
      drone_tick(t);
      break;
    }
    case Channel::Reply:
      on_reply(texts_.items[slot], t);
      texts_.release(slot);
      break;
    case Channel::State:
      state_receiver_->datagram(bytes_of(texts_.items[slot]), t);
      texts_.release(slot);
      if (last_state_arrival_ == t && state_ != LinkState::Connected) {
        state_ = LinkState::Connected;
        if (listener_) listener_->on_link_state(state_, t);
      }
      break;
    case Channel::Video:
      if (link_.h264) {
        const std::span<const std::uint8_t> unit(units_.items[slot]);
        for (std::size_t at = 0; at < unit.size(); at += kTelloVideoDatagramBytes)
          video_receiver_->datagram(unit.subspan(at, std::min(kTelloVideoDatagramBytes, unit.size() - at)), t);
        units_.release(slot);
      } else {
        counters_.add("video_frames");
        if (listener_) listener_->on_video(frames_.items[slot]);
        frames_.release(slot);
      }
      break;
  }
}

void SimTelloLink::on_reply(std::string_view text, Seconds t) {
  counters_.add("replies");
  TelloReply reply;
  if (const ReplyError error = parse_reply(bytes_of(text), reply); error != ReplyError::None) {
    counters_.add(to_string(error));
    return;
  }
  if (const std::optional<CommandOutcome> outcome = channel_.reply(reply, t)) {
    finish(*outcome, t);
  } else {
    counters_.add("tello_reply_unsolicited");
  }
}

// A command ended: the flight phase learns it, SDK mode starts the video (TelloLink::finish).
void SimTelloLink::finish(const CommandOutcome& o, Seconds t) {
  using Result = CommandOutcome::Result;
  state_receiver_->command_finished(o, t);
  if (o.result == Result::TimedOut) counters_.add("tello_command_timed_out");
  else if (o.result == Result::Abandoned) counters_.add("tello_command_abandoned");
  else if (o.result == Result::Error) counters_.add("tello_command_refused");
  else counters_.add("tello_command_ok");
  if (camera_switch_.finished(o)) counters_.add("tello_downvision_refused");
  if (o.command != "command") return;
  if (o.result == Result::Ok) {
    sdk_mode_ = true;
    if (tello_.video) channel_.push("streamon");
    if (const auto down = camera_switch_.after_sdk_mode(); down && tello_.video) channel_.push(*down);
    video_receiver_->reset();
  } else if (!sdk_mode_) {
    channel_.push("command");  // keep knocking until the drone answers
  }
}

void SimTelloLink::supervise(Seconds t) {
  if (state_ == LinkState::Disconnected || state_ == LinkState::Connecting) return;
  const LinkState s = state_after_silence(last_state_arrival_, t, tello_.degraded_after_s, tello_.lost_after_s);
  if (s == state_) return;
  if (s == LinkState::Lost) {
    counters_.add("reconnects");
    enter_sdk_mode();
  }
  state_ = s;
  if (listener_) listener_->on_link_state(state_, t);
}

}  // namespace labo::sim
