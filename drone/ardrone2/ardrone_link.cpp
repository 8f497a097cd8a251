#include "drone/ardrone2/ardrone_link.hpp"

#include <array>
#include <chrono>
#include <stdexcept>

#include "core/config_reader.hpp"
#include "drone/ardrone2/navdata_schema.hpp"
#include "drone/ardrone2/wire_signs.hpp"

namespace labo::ardrone2 {

using replay::RecordChannel;
using replay::RecordingWriter;
using replay::kNoteCameraBottom;
using replay::kNoteCameraFront;
using replay::kNoteVideoConnected;

using namespace ardrone2;

namespace {
constexpr std::size_t kMaxConfigText = 200;  // keeps CONFIG_IDS + CONFIG + REF + PCMD far below 1024 bytes
constexpr int kEmergencyCycles = 10;         // 300 ms of REF with the emergency bit, then cleared
constexpr Seconds kNavdataKickInterval = 0.5;
constexpr Seconds kVideoSilenceTimeout = 2.0;
constexpr std::array<std::uint8_t, 4> kNavdataKick = {1, 0, 0, 0};

void sleep_for(Seconds s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

bool valid_config_text(const std::string& text) {
  return !text.empty() && text.size() <= kMaxConfigText && text.find_first_of("\"\r\n") == std::string::npos;
}
}  // namespace

ArdroneLinkSettings read_ardrone_link_settings(const ConfigReader& c) {
  ArdroneLinkSettings s;
  s.host = c.string_or("host", s.host);
  s.at_port = c.integer_or("at_port", s.at_port, 1, 65535);
  s.navdata_port = c.integer_or("navdata_port", s.navdata_port, 1, 65535);
  s.video_port = c.integer_or("video_port", s.video_port, 1, 65535);
  s.command_interval_s = c.number_or("command_interval_s", s.command_interval_s, Range::closed(0.005, 0.5));
  s.degraded_after_s = c.number_or("degraded_after_s", s.degraded_after_s, Range::closed(0.05, 10.0));
  s.lost_after_s = c.number_or("lost_after_s", s.lost_after_s, Range::closed(0.1, 60.0));
  s.config_ack_timeout_s = c.number_or("config_ack_timeout_s", s.config_ack_timeout_s, Range::closed(0.05, 10.0));
  s.full_navdata = c.boolean_or("full_navdata", s.full_navdata);
  s.video = c.boolean_or("video", s.video);
  s.video_max_bitrate_kbps =
      c.integer_or("video_max_bitrate_kbps", s.video_max_bitrate_kbps, kMinVideoBitrateKbps, kMaxVideoBitrateKbps);
  const std::string rec = c.string_or("recording", "");
  if (!rec.empty()) s.recording = rec;
  if (s.lost_after_s <= s.degraded_after_s) c.fail("lost_after_s", "must be greater than degraded_after_s");
  c.finish();
  return s;
}

ArdroneLink::ArdroneLink(ArdroneLinkSettings settings, Logger logger, const Clock* clock)
    : settings_(std::move(settings)), logger_(std::move(logger)), clock_(clock ? clock : &own_clock_), counters_(logger_),
      status_(logger_, counters_), configs_(settings_.config_ack_timeout_s), video_bitrate_kbps_(settings_.video_max_bitrate_kbps),
      restart_watch_(!settings_.full_navdata) {
  at_buffer_.reserve(kMaxAtDatagramBytes);
}

ArdroneLink::~ArdroneLink() { stop(); }

void ArdroneLink::start() {
  if (running_) return;
  at_endpoint_ = Endpoint::resolve(settings_.host, settings_.at_port);
  navdata_endpoint_ = Endpoint::resolve(settings_.host, settings_.navdata_port);
  video_endpoint_ = Endpoint::resolve(settings_.host, settings_.video_port);
  at_socket_ = Socket::udp(0);
  navdata_socket_ = Socket::udp(0);
  if (!settings_.recording.empty()) recorder_ = std::make_unique<RecordingWriter>(settings_.recording);
  navdata_receiver_ = std::make_unique<NavdataReceiver>(
      counters_, [this](const NavdataSample& s, const NavdataPacket& p) { on_navdata(s, p); });
  video_receiver_ = std::make_unique<VideoReceiver>(
      counters_, [this](const VideoFrame& f) { on_video(f); },
      [this](const EncodedVideo& unit) {
        std::lock_guard lock(listener_mutex_);
        if (listener_) listener_->on_encoded_video(unit);
      });
  queue_startup_config();
  running_ = true;
  set_state(LinkState::Connecting, clock_->now());
  control_thread_ = std::thread([this] { control_loop(); });
  navdata_thread_ = std::thread([this] { navdata_loop(); });
  video_thread_ = std::thread([this] { video_loop(); });
}

void ArdroneLink::stop() {
  if (!running_.exchange(false)) return;
  for (auto* t : {&control_thread_, &navdata_thread_, &video_thread_})
    if (t->joinable()) t->join();
  set_state(LinkState::Disconnected, clock_->now());
  if (recorder_) recorder_->flush();
}

void ArdroneLink::set_listener(DroneLinkListener* listener) {
  std::lock_guard lock(listener_mutex_);
  listener_ = listener;
}

void ArdroneLink::takeoff() {
  std::lock_guard lock(command_mutex_);
  takeoff_ = true;
}

void ArdroneLink::land() {
  std::lock_guard lock(command_mutex_);
  takeoff_ = false;
  pcmd_ = WirePcmd{};
}

void ArdroneLink::emergency() {
  std::lock_guard lock(command_mutex_);
  takeoff_ = false;
  pcmd_ = WirePcmd{};
  emergency_cycles_ = kEmergencyCycles;
}

void ArdroneLink::flat_trim() {
  std::lock_guard lock(command_mutex_);
  flat_trim_ = true;
}

void ArdroneLink::calibrate_magnetometer() {
  std::lock_guard lock(command_mutex_);
  calibrate_ = true;
}

void ArdroneLink::move(const MoveCommand& command) {
  std::lock_guard lock(command_mutex_);
  pcmd_ = move_to_wire(command);
}

void ArdroneLink::hover() {
  std::lock_guard lock(command_mutex_);
  pcmd_ = WirePcmd{};
}

void ArdroneLink::select_camera(CameraId camera) {
  // Drone 2: video:video_channel 0 = front, 1 = bottom.
  set_config("video:video_channel", camera == CameraId::Bottom ? "1" : "0");
  std::lock_guard lock(command_mutex_);
  requested_camera_ = camera;
}

void ArdroneLink::set_config(const std::string& key, const std::string& value) {
  if (!valid_config_text(key) || !valid_config_text(value) || key.find(':') == std::string::npos)
    throw std::invalid_argument("AR.Drone config: key 'section:name' and value of 1.." + std::to_string(kMaxConfigText) +
                                " characters without quotes or line breaks expected, got '" + key + "'='" + value + "'");
  std::lock_guard lock(command_mutex_);
  configs_.push_back({key, value});
}

LinkState ArdroneLink::state() const { return status_.state(); }

int ArdroneLink::video_bitrate_kbps() const {
  std::lock_guard lock(command_mutex_);
  return video_bitrate_kbps_;
}

void ArdroneLink::set_video_bitrate_kbps(int kbps) {
  if (kbps < kMinVideoBitrateKbps || kbps > kMaxVideoBitrateKbps)
    throw std::invalid_argument("AR.Drone 2.0 video bit rate: " + std::to_string(kMinVideoBitrateKbps) + ".." +
                                std::to_string(kMaxVideoBitrateKbps) + " kbit/s expected, got " + std::to_string(kbps));
  std::lock_guard lock(command_mutex_);
  video_bitrate_kbps_ = kbps;
  for (auto& [key, value] : video_bitrate_configs(kbps)) configs_.push_back({key, value});
}

LinkStatistics ArdroneLink::statistics() const { return counters_.snapshot(); }

void ArdroneLink::queue_startup_config() {
  std::lock_guard lock(command_mutex_);
  // Startup configs go first, ahead of anything the user queued.
  if (settings_.full_navdata) {
    configs_.push_front({"general:navdata_demo", "FALSE"});
  } else {
    configs_.push_front({"general:navdata_demo", "TRUE"});
  }
  // The video keys are K_SHALLOW in the SDK's config table (not kept across a reboot): sent every time.
  for (auto& [key, value] : video_bitrate_configs(video_bitrate_kbps_)) configs_.push_back({key, value});
  if (requested_camera_ == CameraId::Bottom) configs_.push_back({"video:video_channel", "1"});
  configs_.restart();
}

void ArdroneLink::record(RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes) {
  if (recorder_) recorder_->write(channel, t, bytes);
}

void ArdroneLink::set_state(LinkState s, Seconds t) {
  status_.set(s, t, recorder_.get(), [this](LinkState state, Seconds when) {
    std::lock_guard lock(listener_mutex_);
    if (listener_) listener_->on_link_state(state, when);
  });
}

// ---- control thread ----------------------------------------------------------------------------

void ArdroneLink::control_loop() {
  auto next = std::chrono::steady_clock::now();
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(settings_.command_interval_s));
  while (running_) {
    const Seconds t = clock_->now();
    supervise(t);
    send_commands(t);
    status_.update_rates(t, "navdata_packets");
    next += period;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) {  // overloaded machine: skip the missed ticks rather than bursting
      counters_.add("at_ticks_late");
      next = now;
    }
    std::this_thread::sleep_until(next);
  }
}

void ArdroneLink::supervise(Seconds t) {
  const LinkState s = state_after_silence(last_navdata_t_.load(), t, settings_.degraded_after_s, settings_.lost_after_s);
  const LinkState before = state();
  // Reconnect without restarting: navdata restarts from the kick packet (the navdata thread repeats
  // it while silent).
  if (s == LinkState::Lost && before != LinkState::Lost) redo_startup("reconnects");
  set_state(s, t);
}

void ArdroneLink::redo_startup(const char* counter) {
  counters_.add(counter);
  {
    std::lock_guard lock(command_mutex_);
    reset_sequence_ = true;  // AT seq 1 resets the drone's counter
  }
  queue_startup_config();
  restart_watch_reset_ = true;
  reset_video_ = true;
}

void ArdroneLink::send_commands(Seconds t) {
  const std::uint32_t state = drone_state_.load();
  {
    std::lock_guard lock(command_mutex_);
    at_buffer_.clear();
    // While the drone reports that no command reached it (the com-watchdog bit), every datagram
    // starts the sequence again at 1: the one datagram that carried the reset after a reconnect may
    // have been lost with the link, and the drone then drops every later number as old (tested in
    // "wifi relay: after a cut the link is lost, then the driver's commands reach the drone again").
    if (reset_sequence_ || (state & state_mask(kStateComWatchdog))) {
      encoder_.reset_sequence();
      reset_sequence_ = false;
    }
    if (state & state_mask(kStateComWatchdog)) {
      encoder_.comwdg(at_buffer_);
      counters_.add("at_comwdg");
    }
    if (flat_trim_) {
      encoder_.ftrim(at_buffer_);
      flat_trim_ = false;
    }
    if (calibrate_) {
      encoder_.calib(at_buffer_, 0);  // device 0 = magnetometer; the drone accepts it only in flight
      calibrate_ = false;
    }
    run_config_handshake(t, state);
    encoder_.ref(at_buffer_, takeoff_, emergency_cycles_ > 0);
    if (emergency_cycles_ > 0) --emergency_cycles_;
    encoder_.pcmd(at_buffer_, pcmd_);
  }
  const auto bytes = std::span(reinterpret_cast<const std::uint8_t*>(at_buffer_.data()), at_buffer_.size());
  if (bytes.size() > kMaxAtDatagramBytes) {  // cannot happen with config text <= 200 characters; never send it
    counters_.bad_input("at_datagram_oversize", t, std::to_string(bytes.size()) + " bytes");
    return;
  }
  if (at_socket_.send_to(bytes, at_endpoint_)) {
    counters_.add("at_datagrams");
  } else {
    counters_.add("at_send_failed");
  }
  record(RecordChannel::AtOut, t, bytes);
}

// Called with command_mutex_ held.
void ArdroneLink::run_config_handshake(Seconds t, std::uint32_t state) {
  const Seconds last = last_navdata_t_.load();
  const bool alive = last >= 0 && t - last <= settings_.degraded_after_s;
  const ConfigTick tick = configs_.tick(t, state & state_mask(kStateCommandAck), alive, encoder_, at_buffer_);
  if (tick.sent) counters_.add("config_sent");
  if (tick.timed_out) counters_.bad_input("config_ack_timeout", t, *tick.timed_out);
  if (!tick.acked) return;
  counters_.add("config_acked");
  if (recorder_) recorder_->note(t, "config_acked " + tick.acked->key + "=" + tick.acked->value);
  if (tick.acked->key == "video:video_channel") {
    active_camera_ = tick.acked->value == "1" || tick.acked->value == "3" ? CameraId::Bottom : CameraId::Front;
    reset_video_decoder_ = true;
  }
}

// ---- navdata thread ----------------------------------------------------------------------------

void ArdroneLink::navdata_loop() {
  std::vector<std::uint8_t> buffer(65536);
  Seconds last_kick = -1e9;
  Endpoint from;
  while (running_) {
    const Seconds now = clock_->now();
    const Seconds last = last_navdata_t_.load();
    if ((last < 0 || now - last > kNavdataKickInterval) && now - last_kick > kNavdataKickInterval) {
      // Start-up and reconnection: the drone streams to whoever sends to its port 5554.
      navdata_socket_.send_to(kNavdataKick, navdata_endpoint_);
      record(RecordChannel::NavdataOut, now, kNavdataKick);
      counters_.add("navdata_kicks");
      last_kick = now;
      navdata_receiver_->reset_sequence();
    }
    const long n = navdata_socket_.receive_from(buffer, from, 0.05);
    if (n < 0) continue;
    const Seconds t = clock_->now();
    if (static_cast<std::size_t>(n) > buffer.size()) {
      counters_.bad_input("navdata_datagram_too_large", t, std::to_string(n) + " bytes");
      continue;
    }
    if (from.addr.sin_addr.s_addr != navdata_endpoint_.addr.sin_addr.s_addr) {
      counters_.bad_input("navdata_foreign_sender", t, "datagram from another host");
      continue;
    }
    const auto bytes = std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n));
    record(RecordChannel::NavdataIn, t, bytes);
    navdata_receiver_->datagram(bytes, t);
  }
}

void ArdroneLink::on_navdata(const NavdataSample& sample, const NavdataPacket& packet) {
  drone_state_ = sample.state;
  last_navdata_t_ = sample.t;
  if (restart_watch_reset_.exchange(false)) restart_watch_.configuring();
  // A drone that restarted faster than lost_after_s keeps the link Connected with its bootstrap
  // packets: only the packets tell (test "link: a drone restarted faster than the link's loss is
  // configured again").
  if (restart_watch_.restarted(packet, navdata_receiver_->sequence_restarted())) {
    if (recorder_) recorder_->note(sample.t, "drone_restarted");
    redo_startup("drone_restarts");
  }
  // A bootstrap packet (no demo option) keeps the link alive but has no values: its sample would
  // say battery 0 and control state 0. Test "link conformance: the AR.Drone link ...".
  if (!packet.has(kTagDemo)) return;
  std::lock_guard lock(listener_mutex_);
  if (listener_) listener_->on_navdata(sample);
}

// ---- video thread ------------------------------------------------------------------------------

void ArdroneLink::video_loop() {
  std::vector<std::uint8_t> buffer(64 * 1024);
  while (running_) {
    if (!settings_.video) {
      sleep_for(0.1);
      continue;
    }
    Socket tcp = Socket::tcp_connect(video_endpoint_, 1.0);
    if (!tcp.valid()) {
      counters_.add("video_connect_failed");
      sleep_for(0.5);
      continue;
    }
    counters_.add("video_connects");
    reset_video_ = false;
    video_receiver_->reset();
    if (recorder_) recorder_->note(clock_->now(), kNoteVideoConnected);
    Seconds last_data = clock_->now();
    while (running_ && !reset_video_) {
      if (reset_video_decoder_.exchange(false)) {
        // Noted from this thread, in order with the video bytes, so a replay switches at the same byte.
        const CameraId camera = active_camera_.load();
        if (recorder_) recorder_->note(clock_->now(), camera == CameraId::Bottom ? kNoteCameraBottom : kNoteCameraFront);
        video_receiver_->set_camera(camera);
        video_receiver_->reset();
      }
      const long n = tcp.receive(buffer, 0.1);
      const Seconds t = clock_->now();
      if (n < 0) {
        counters_.add("video_disconnects");
        break;
      }
      if (n == 0) {
        if (t - last_data > kVideoSilenceTimeout) {
          counters_.add("video_timeouts");
          break;
        }
        continue;
      }
      last_data = t;
      const auto bytes = std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n));
      record(RecordChannel::VideoIn, t, bytes);
      video_receiver_->bytes(bytes, t);
    }
  }
}

void ArdroneLink::on_video(const VideoFrame& frame) {
  std::lock_guard lock(listener_mutex_);
  if (listener_) listener_->on_video(frame);
}

}  // namespace labo::ardrone2
