#include "drone/tello/tello_emulator.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "core/config_reader.hpp"
#include "drone/ardrone2/h264_codec.hpp"
#include "drone/tello/annexb_assembler.hpp"
#include "drone/tello/tello_camera_switch.hpp"
#include "drone/tello/tello_command.hpp"

namespace labo::tello {

using namespace tello;
using ardrone2::Endpoint;
using ardrone2::Socket;

namespace {
constexpr Seconds kCommandPollS = 0.005;  // motion replies and the watchdog are checked this often
void sleep_for(Seconds s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

// A periodic loop's tick: true at or after `next` (then `next` moves one period on, never into the
// past: an overloaded machine skips ticks rather than bursting); false after a short sleep before it.
bool tick_due(const SteadyClock& clock, Seconds& next, Seconds period, Seconds& t) {
  t = clock.now();
  if (t < next) {
    sleep_for(std::min(next - t, 0.05));
    return false;
  }
  next = std::max(next + period, t);
  return true;
}

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}
}  // namespace

TelloEmulatorSettings read_tello_emulator_settings(const ConfigReader& c) {
  TelloEmulatorSettings s;
  s.bind_host = c.string_or("bind_host", s.bind_host);
  s.command_port = c.integer_or("command_port", s.command_port, 0, 65535);
  s.client_state_port = c.integer_or("client_state_port", s.client_state_port, 1, 65535);
  s.client_video_port = c.integer_or("client_video_port", s.client_video_port, 1, 65535);
  s.state_rate_hz = c.number_or("state_rate_hz", s.state_rate_hz, Range::closed(1, 100));
  s.video_fps = c.number_or("video_fps", s.video_fps, Range::closed(1, 60));
  s.video_width = c.integer_or("video_width", s.video_width, 16, 1920);
  s.video_height = c.integer_or("video_height", s.video_height, 16, 1080);
  if (s.video_width % 2 || s.video_height % 2) c.fail("video_width", "video_width and video_height must be even");
  s.video_gop = c.integer_or("video_gop", s.video_gop, 1, 300);
  s.video_bitrate_kbps = c.integer_or("video_bitrate_kbps", s.video_bitrate_kbps, 100, 20000);
  s.firmware.reply_delay_s = c.number_or("reply_delay_s", s.firmware.reply_delay_s, Range::closed(0, 5));
  s.firmware.watchdog_s = c.number_or("watchdog_s", s.firmware.watchdog_s, Range::closed(0.5, 600));
  s.firmware.motion_timeout_s = c.number_or("motion_timeout_s", s.firmware.motion_timeout_s, Range::closed(1, 60));
  s.firmware.downvision = c.boolean_or("downvision", s.firmware.downvision);
  c.finish();
  return s;
}

TelloEmulator::TelloEmulator(EmulatedVehicle& vehicle, TelloEmulatorSettings settings, Logger logger)
    : vehicle_(vehicle), settings_(std::move(settings)), logger_(std::move(logger)), counters_(logger_),
      client_state_port_(settings_.client_state_port), client_video_port_(settings_.client_video_port),
      firmware_(settings_.firmware, counters_) {}

TelloEmulator::~TelloEmulator() { stop(); }

void TelloEmulator::start() {
  if (running_) return;
  command_socket_ = Socket::udp(settings_.command_port, settings_.bind_host);
  stream_socket_ = Socket::udp(0, settings_.bind_host);
  command_port_ = command_socket_.local_port();
  running_ = true;
  logger_.info(clock_.now(), "Tello emulator listening").kv("command_port", command_port_);
  command_thread_ = std::thread([this] { command_loop(); });
  state_thread_ = std::thread([this] { state_loop(); });
  video_thread_ = std::thread([this] { video_loop(); });
}

void TelloEmulator::stop() {
  if (!running_.exchange(false)) return;
  for (auto* t : {&command_thread_, &state_thread_, &video_thread_})
    if (t->joinable()) t->join();
}

void TelloEmulator::set_client_ports(int state_port, int video_port) {
  client_state_port_ = state_port;
  client_video_port_ = video_port;
}

bool TelloEmulator::client(Endpoint& state_to, Endpoint& video_to) const {
  std::lock_guard lock(client_mutex_);
  if (!have_client_) return false;
  state_to = video_to = client_;
  state_to.addr.sin_port = htons(static_cast<std::uint16_t>(client_state_port_.load()));
  video_to.addr.sin_port = htons(static_cast<std::uint16_t>(client_video_port_.load()));
  return true;
}

// ---- commands ----------------------------------------------------------------------------------

void TelloEmulator::command_loop() {
  std::array<std::uint8_t, 2048> buffer;
  Endpoint from;
  pending_.reserve(16);
  while (running_) {
    const long n = command_socket_.receive_from(buffer, from, kCommandPollS);
    const Seconds t = clock_.now();
    std::optional<TelloFirmware::Reply> reply;
    if (n >= 0) {
      counters_.add("command_datagrams");
      const auto bytes = std::span<const std::uint8_t>(buffer.data(), std::min<std::size_t>(static_cast<std::size_t>(n), buffer.size()));
      std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
      const bool is_text = static_cast<std::size_t>(n) <= kMaxCommandBytes &&
                           (valid_command_text(text) || text.starts_with("rc "));
      if (!is_text) {
        counters_.bad_input("command_malformed", t, std::to_string(n) + " bytes, expected an SDK text command");
      } else {
        std::lock_guard lock(vehicle_mutex_);
        reply = firmware_.command(text, vehicle_, t);
        if (text == "command") {  // state and video go to whoever entered SDK mode last
          std::lock_guard client_lock(client_mutex_);
          client_ = from;
          have_client_ = true;
        }
      }
      last_sender_ = from;
      if (reply) pending_.push_back({std::move(reply->text), reply->due_t, from});
    }
    {
      std::lock_guard lock(vehicle_mutex_);
      reply = firmware_.advance(vehicle_, t);
    }
    if (reply) pending_.push_back({std::move(reply->text), reply->due_t, last_sender_});
    send_due_replies(t);
  }
}

void TelloEmulator::send_due_replies(Seconds t) {
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (it->due_t > t) {
      ++it;
      continue;
    }
    if (command_socket_.send_to(bytes_of(it->text), it->to)) counters_.add("replies_sent");
    it = pending_.erase(it);
  }
}

// ---- state -------------------------------------------------------------------------------------

void TelloEmulator::state_loop() {
  std::string text;
  text.reserve(kMaxStateBytes);
  Endpoint state_to, video_to;
  const Seconds period = 1.0 / settings_.state_rate_hz;
  Seconds next = clock_.now(), t = 0;
  while (running_) {
    if (!tick_due(clock_, next, period, t)) continue;
    TelloState state;
    {
      std::lock_guard lock(vehicle_mutex_);
      if (!firmware_.sdk_mode()) continue;
      vehicle_.advance_to(t);
      state = firmware_.state(vehicle_.telemetry());
    }
    if (!client(state_to, video_to)) continue;
    format_tello_state(state, text);
    if (stream_socket_.send_to(bytes_of(text), state_to)) counters_.add("state_sent");
  }
}

// ---- video -------------------------------------------------------------------------------------

void TelloEmulator::video_loop() {
  ardrone2::H264EncoderSettings es;
  es.width = settings_.video_width;
  es.height = settings_.video_height;
  es.fps = static_cast<int>(std::lround(settings_.video_fps));
  es.gop = settings_.video_gop;
  es.bitrate_kbps = settings_.video_bitrate_kbps;
  std::unique_ptr<ardrone2::H264Encoder> encoder;
  ardrone2::EncodedFrame encoded;
  cv::Mat image;
  Endpoint state_to, video_to;
  const Seconds period = 1.0 / settings_.video_fps;
  Seconds next = clock_.now(), t = 0;
  while (running_) {
    if (!tick_due(clock_, next, period, t)) continue;
    {
      std::lock_guard lock(vehicle_mutex_);
      if (!firmware_.streaming()) continue;
      if (firmware_.take_stream_restart()) encoder.reset();
      vehicle_.advance_to(t);
      firmware_.render_stream(vehicle_, image);  // the front camera, or the downward one after "downvision 1"
    }
    if (!client(state_to, video_to)) continue;
    if (image.empty() || image.type() != CV_8UC3) continue;  // a scheduled video dropout: no frame
    if (!encoder) {  // a new stream starts with an IDR, at its camera's size
      const bool down = image.cols == kDownvisionWidth && image.rows == kDownvisionHeight;
      es.width = down ? kDownvisionWidth : settings_.video_width;
      es.height = down ? kDownvisionHeight : settings_.video_height;
      encoder = std::make_unique<ardrone2::H264Encoder>(es);
    }
    if (!encoder->encode(image, encoded)) {
      counters_.add("video_encode_failed");
      continue;
    }
    const std::span<const std::uint8_t> unit(encoded.data);
    for (std::size_t at = 0; at < unit.size(); at += kTelloVideoDatagramBytes) {
      const auto piece = unit.subspan(at, std::min(kTelloVideoDatagramBytes, unit.size() - at));
      if (!stream_socket_.send_to(piece, video_to)) counters_.add("video_send_failed");
    }
    counters_.add("video_frames_sent");
  }
}

}  // namespace labo::tello
