#include "drone/sim/sim_drone_link.hpp"

#include <algorithm>
#include <cmath>

#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/navdata_schema.hpp"
#include "core/cpu_time.hpp"

namespace labo::sim {

using ardrone2::state_mask;

struct SimDroneLink::VideoStream {
  ardrone2::H264Encoder encoder;
  ardrone2::H264Decoder decoder;
  ardrone2::EncodedFrame encoded;
  explicit VideoStream(const ardrone2::H264EncoderSettings& s) : encoder(s) {}
};

namespace {

double clip_unit(double v) { return std::clamp(v, -1.0, 1.0); }

}  // namespace

SimDroneLink::SimDroneLink(SimulatedLab& lab, SimLinkSettings settings)
    : lab_(lab),
      settings_(settings),
      rng_(settings.seed ^ 0x5eed11c0ffeeULL),
      now_(lab.now()),
      demo_(!settings.full_navdata) {
  next_command_ = next_navdata_ = next_frame_ = now_;
  last_command_arrival_ = last_navdata_arrival_sent_ = last_video_arrival_ = now_;
  // The driver's bit-rate configs go out with the first AT datagram, as ArdroneLink queues them.
  for (const auto& [key, value] : ardrone2::video_bitrate_configs(settings_.video_bitrate_kbps)) set_config(key, value);
  if (settings_.h264) {
    ardrone2::H264EncoderSettings es;
    es.fps = static_cast<int>(std::lround(settings_.video_fps));
    es.bitrate_kbps = drone_bitrate_.streaming_kbps();
    for (int i = 0; i < (settings_.both_cameras ? 2 : 1); ++i) streams_.push_back(std::make_unique<VideoStream>(es));
  }
}

SimDroneLink::~SimDroneLink() = default;

void SimDroneLink::move(const MoveCommand& c) {
  if (!(std::isfinite(c.roll) && std::isfinite(c.pitch) && std::isfinite(c.gaz) && std::isfinite(c.yaw_rate))) {
    hover_ = true;
    return;
  }
  move_ = {clip_unit(c.roll), clip_unit(c.pitch), clip_unit(c.gaz), clip_unit(c.yaw_rate)};
  hover_ = false;
}

void SimDroneLink::set_config(const std::string& key, const std::string& value) {
  if (key == "general:navdata_demo") {
    pending_demo_ = value == "TRUE";
  } else if (key == "video:video_channel" && (value == "0" || value == "2")) {
    select_camera(CameraId::Front);
  } else if (key == "video:video_channel" && (value == "1" || value == "3")) {
    select_camera(CameraId::Bottom);
  } else if (ardrone2::VideoBitrateControl::is_key(key) && requested_bitrate_.apply(key, value)) {
    pending_bitrate_ = true;
  } else {
    ++counters_.config_ignored;
  }
}

LinkStatistics SimDroneLink::statistics() const {
  LinkStatistics s;
  const Counters& c = counters_;
  s.counters = {{"navdata_packets", c.navdata_packets},   {"navdata_lost", c.navdata_lost},
                {"video_frames", c.video_frames},         {"video_lost", c.video_lost},
                {"video_dropout", c.video_dropout},       {"video_waiting_for_idr", c.video_waiting_for_idr},
                {"commands_sent", c.commands_sent},       {"commands_lost", c.commands_lost},
                {"config_ignored", c.config_ignored},     {"camera_switches", c.camera_switches},
                {"video_bitrate_changes", c.video_bitrate_changes},
                {"video_bitrate_kbps", static_cast<std::uint64_t>(drone_bitrate_.streaming_kbps())}};
  if (now_ > 0) {
    s.navdata_rate_hz = static_cast<double>(c.navdata_packets) / now_;
    s.video_fps = static_cast<double>(c.video_frames) / now_;
  }
  return s;
}

// ---- the lockstep loop -------------------------------------------------------------------------

void SimDroneLink::advance_to(Seconds t) {
  if (state_ == LinkState::Disconnected) {
    state_ = LinkState::Connecting;
    if (listener_) listener_->on_link_state(state_, now_);
  }
  for (;;) {
    const Seconds delivery = queue_.empty() ? t + 1.0 : queue_.top().t;
    const Seconds next = std::min({delivery, next_command_, next_navdata_, next_frame_});
    if (next > t) break;
    now_ = next;
    if (delivery == next) {
      const auto d = queue_.pop();
      deliver(d.channel, d.slot, d.t);
    } else if (next_command_ == next) {
      send_commands(next);
      next_command_ = next + settings_.command_interval_s;
    } else if (next_navdata_ == next) {
      generate_navdata(next);
      next_navdata_ = next + 1.0 / (demo_ ? settings_.demo_rate_hz : settings_.full_rate_hz);
    } else {
      generate_video(next);
      next_frame_ = next + 1.0 / settings_.video_fps;
    }
  }
  now_ = std::max(now_, t);
  lab_.advance_to(now_);
  supervise(now_);
}

// In-order delivery (one channel never overtakes itself), never before it was sent.
Seconds SimDroneLink::arrival(Seconds t, Seconds delay, Seconds& last_arrival) {
  const double jitter = settings_.jitter_s > 0 ? settings_.jitter_s * normal_(rng_) : 0.0;
  last_arrival = std::max({last_arrival, t, t + delay + jitter});
  return last_arrival;
}

void SimDroneLink::send_commands(Seconds t) {
  CommandPacket p;
  p.takeoff_bit = takeoff_bit_;
  p.emergency_bit = emergency_ticks_ > 0;
  emergency_ticks_ = std::max(0, emergency_ticks_ - 1);
  p.flat_trim = flat_trim_;
  p.hover = hover_;
  p.move = move_;
  p.camera = pending_camera_;
  p.demo = pending_demo_;
  if (pending_bitrate_) p.video_bitrate = requested_bitrate_;
  ++counters_.commands_sent;
  if (lost(settings_.command_loss) || lab_.link_outage(t)) {
    ++counters_.commands_lost;  // one-off requests go again with the next datagram, as the driver resends them
    return;
  }
  flat_trim_ = false;
  if (pending_camera_ && settings_.h264 && !settings_.both_cameras) streams_.front()->decoder.reset();  // wait for an IDR
  pending_camera_.reset();
  pending_demo_.reset();
  pending_bitrate_ = false;
  const std::size_t slot = commands_.acquire();
  commands_.items[slot] = p;
  schedule(arrival(t, settings_.command_delay_s, last_command_arrival_), Channel::Command, slot);
}

void SimDroneLink::generate_navdata(Seconds t) {
  lab_.advance_to(t);
  if (lost(settings_.navdata_loss) || lab_.link_outage(t)) {
    ++counters_.navdata_lost;
    return;
  }
  const VehicleTelemetry tel = lab_.telemetry();
  const std::size_t slot = navdata_.acquire();
  NavdataSample& s = navdata_.items[slot];
  s = tel.nav;
  s.sequence = ++sequence_;
  s.state = state_bits(tel);
  s.has_drone_time = !demo_;  // the time option is part of full navdata
  s.drone_time = t;
  s.t = arrival(t, settings_.navdata_delay_s, last_navdata_arrival_sent_);
  schedule(s.t, Channel::Navdata, slot);
}

void SimDroneLink::generate_video(Seconds t) {
  lab_.advance_to(t);
  if (switching_to_ && t >= switch_at_) {
    lab_.select_camera(*switching_to_, t);
    switching_to_.reset();
    ++counters_.camera_switches;
  }
  if (lab_.video_dropout()) {
    ++counters_.video_dropout;
    return;
  }
  if (lost(settings_.video_loss) || lab_.link_outage(t)) {
    ++counters_.video_lost;
    return;
  }
  const Seconds arrive = arrival(t, settings_.video_delay_s, last_video_arrival_);
  if (settings_.both_cameras) {
    render_frame(CameraId::Front, arrive);
    render_frame(CameraId::Bottom, arrive);
  } else {
    render_frame(lab_.selected_camera(), arrive);
  }
}

void SimDroneLink::render_frame(CameraId camera, Seconds arrive) {
  const std::size_t slot = frames_.acquire();
  VideoFrame& f = frames_.items[slot];
  f.t = arrive;
  f.camera = camera;
  if (!settings_.h264) {
    lab_.render(camera, f.bgr);
  } else {
    lab_.render(camera, rendered_);
    VideoStream& stream = *streams_[settings_.both_cameras ? static_cast<std::size_t>(camera) : 0];
    const double start = process_cpu_seconds();
    const bool encoded = !rendered_.empty() && stream.encoder.encode(rendered_, stream.encoded);
    const auto status = encoded ? stream.decoder.decode(stream.encoded.data, f.bgr) : ardrone2::DecodeStatus::Error;
    profile_.codec_s += process_cpu_seconds() - start;
    ++profile_.encoded;
    if (status != ardrone2::DecodeStatus::Decoded) {
      if (status == ardrone2::DecodeStatus::WaitingForIdr) ++counters_.video_waiting_for_idr;
      frames_.release(slot);
      return;
    }
  }
  f.frame_number = frame_number_++;
  schedule(arrive, Channel::Video, slot);
}

void SimDroneLink::deliver(Channel channel, std::size_t slot, Seconds t) {
  switch (channel) {
    case Channel::Command:
      apply_commands(commands_.items[slot], t);
      commands_.release(slot);
      break;
    case Channel::Navdata:
      ++counters_.navdata_packets;
      last_navdata_arrival_ = t;
      if (state_ != LinkState::Connected) {
        state_ = LinkState::Connected;
        if (listener_) listener_->on_link_state(state_, t);
      }
      if (listener_) listener_->on_navdata(navdata_.items[slot]);
      navdata_.release(slot);
      break;
    case Channel::Video:
      ++counters_.video_frames;
      if (listener_) listener_->on_video(frames_.items[slot]);
      frames_.release(slot);
      break;
  }
}

// The firmware's side of one AT datagram, as ArdroneEmulator::handle_command does it.
void SimDroneLink::apply_commands(const CommandPacket& p, Seconds t) {
  lab_.advance_to(t);
  if (p.emergency_bit && !drone_emergency_bit_) lab_.emergency(t);  // the toggle acts on its rising edge
  drone_emergency_bit_ = p.emergency_bit;
  // ArdroneLink writes AT*FTRIM before AT*REF in a datagram: a flat trim sent with the take-off acts
  // while the drone is still on the ground.
  if (p.flat_trim) lab_.flat_trim(t);
  if (p.takeoff_bit && !drone_takeoff_bit_) lab_.takeoff(t);
  if (!p.takeoff_bit) lab_.land(t);  // on the level, as the emulator: landing a landed drone does nothing
  drone_takeoff_bit_ = p.takeoff_bit;
  if (p.camera) {
    switching_to_ = *p.camera;
    switch_at_ = t + settings_.camera_switch_delay_s;
  }
  if (p.video_bitrate) {
    drone_bitrate_ = *p.video_bitrate;
    for (auto& stream : streams_) {
      if (stream->encoder.settings().bitrate_kbps == drone_bitrate_.streaming_kbps()) continue;
      stream->encoder.set_bitrate_kbps(drone_bitrate_.streaming_kbps());  // from the next frame (an IDR)
      ++counters_.video_bitrate_changes;
    }
  }
  if (p.demo) demo_ = *p.demo;
  lab_.move(p.move, p.hover, t);
}

void SimDroneLink::supervise(Seconds t) {
  if (state_ != LinkState::Connected && state_ != LinkState::Degraded && state_ != LinkState::Lost) return;
  const Seconds silence = t - last_navdata_arrival_;
  const LinkState s = silence > settings_.lost_after_s       ? LinkState::Lost
                      : silence > settings_.degraded_after_s ? LinkState::Degraded
                                                             : LinkState::Connected;
  if (s != state_) {
    state_ = s;
    if (listener_) listener_->on_link_state(state_, t);
  }
}

std::uint32_t SimDroneLink::state_bits(const VehicleTelemetry& tel) const {
  std::uint32_t s = state_mask(ardrone2::kStateVideoEnabled);
  if (tel.flying) s |= state_mask(ardrone2::kStateFlying);
  if (tel.battery_low) s |= state_mask(ardrone2::kStateBatteryLow);
  if (tel.motors_cut) s |= state_mask(ardrone2::kStateCutout);
  if (tel.emergency) s |= state_mask(ardrone2::kStateEmergency);
  if (demo_) s |= state_mask(ardrone2::kStateNavdataDemo);
  return s;
}

}  // namespace labo::sim
