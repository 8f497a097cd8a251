#include "drone/ardrone2/ardrone_emulator.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/config_reader.hpp"
#include "drone/ardrone2/h264_codec.hpp"
#include "drone/ardrone2/navdata_builder.hpp"
#include "drone/ardrone2/navdata_schema.hpp"
#include "drone/ardrone2/pave.hpp"
#include "drone/ardrone2/wire_signs.hpp"

namespace labo::ardrone2 {

using namespace ardrone2;

namespace {
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kG = 9.80665;
void sleep_for(Seconds s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }
}  // namespace

ArdroneEmulatorSettings read_ardrone_emulator_settings(const ConfigReader& c) {
  ArdroneEmulatorSettings s;
  s.bind_host = c.string_or("bind_host", s.bind_host);
  s.at_port = c.integer_or("at_port", s.at_port, 0, 65535);
  s.navdata_port = c.integer_or("navdata_port", s.navdata_port, 0, 65535);
  s.video_port = c.integer_or("video_port", s.video_port, 0, 65535);
  s.demo_rate_hz = c.number_or("demo_rate_hz", s.demo_rate_hz, Range::closed(1, 1000));
  s.full_rate_hz = c.number_or("full_rate_hz", s.full_rate_hz, Range::closed(1, 1000));
  s.video_fps = c.number_or("video_fps", s.video_fps, Range::closed(1, 60));
  s.video_bitrate_kbps = c.integer_or("video_bitrate_kbps", s.video_bitrate_kbps, 100, 20000);
  s.camera_switch_delay_s = c.number_or("camera_switch_delay_s", s.camera_switch_delay_s, Range::closed(0, 10));
  s.com_watchdog_s = c.number_or("com_watchdog_s", s.com_watchdog_s, Range::closed(0.01, 10));
  c.finish();
  return s;
}

ArdroneEmulator::ArdroneEmulator(EmulatedVehicle& vehicle, ArdroneEmulatorSettings settings, Logger logger)
    : vehicle_(vehicle), settings_(std::move(settings)), logger_(std::move(logger)), time_origin_(vehicle.now()),
      counters_(logger_), bitrate_(settings_.video_bitrate_kbps), streaming_bitrate_kbps_(settings_.video_bitrate_kbps) {}

ArdroneEmulator::~ArdroneEmulator() { stop(); }

void ArdroneEmulator::start() {
  if (running_) return;
  at_socket_ = Socket::udp(settings_.at_port, settings_.bind_host);
  navdata_socket_ = Socket::udp(settings_.navdata_port, settings_.bind_host);
  video_listener_ = Socket::tcp_listen(settings_.video_port, settings_.bind_host);
  at_port_ = at_socket_.local_port();
  navdata_port_ = navdata_socket_.local_port();
  video_port_ = video_listener_.local_port();
  running_ = true;
  logger_.info(now(), "AR.Drone 2.0 emulator listening")
      .kv("at_port", at_port_).kv("navdata_port", navdata_port_).kv("video_port", video_port_);
  at_thread_ = std::thread([this] { at_loop(); });
  navdata_thread_ = std::thread([this] { navdata_loop(); });
  video_thread_ = std::thread([this] { video_loop(); });
}

void ArdroneEmulator::stop() {
  if (!running_.exchange(false)) return;
  for (auto* t : {&at_thread_, &navdata_thread_, &video_thread_})
    if (t->joinable()) t->join();
}

// ---- AT commands -------------------------------------------------------------------------------

void ArdroneEmulator::at_loop() {
  std::vector<std::uint8_t> buffer(4096);
  std::vector<AtCommand> commands;
  AtCommandParser parser;
  AtSequenceFilter sequence;
  Endpoint from;
  while (running_) {
    const long n = at_socket_.receive_from(buffer, from, 0.05);
    if (n < 0) continue;
    const Seconds t = now();
    counters_.add("at_datagrams");
    if (static_cast<std::size_t>(n) > buffer.size()) {
      counters_.bad_input("at_datagram_too_long", t, std::to_string(n) + " bytes");
      continue;
    }
    const std::string_view text(reinterpret_cast<const char*>(buffer.data()), static_cast<std::size_t>(n));
    const AtParseReport report = parser.parse(text, commands);
    if (report.datagram_too_long) counters_.bad_input("at_datagram_too_long", t, report.first_error);
    if (report.malformed > 0) counters_.bad_input("at_malformed", t, report.first_error);
    for (const auto& c : commands) {
      if (!sequence.accept(c.sequence)) {
        counters_.add("at_old_sequence");
        continue;
      }
      handle_command(c, t);
    }
  }
}

void ArdroneEmulator::handle_command(const AtCommand& c, Seconds t) {
  counters_.add("at_" + c.name);
  {
    std::lock_guard lock(state_mutex_);
    last_at_t_ = t;
  }
  if (c.name == "REF") {
    const auto input = static_cast<std::uint32_t>(c.args[0].integer);
    const bool takeoff = input & kRefTakeoffBit, emergency = input & kRefEmergencyBit;
    bool do_takeoff = false, do_land = false, do_emergency = false;
    {
      std::lock_guard lock(state_mutex_);
      do_takeoff = takeoff && !takeoff_bit_;
      // Take-off acts on the bit's rising edge, landing on its level: a drone in the air that hears
      // "land" lands, even when it never heard the take-off that this emulator's firmware state
      // remembers (an emulator restarted over a flying vehicle, a client that joined in flight).
      do_land = !takeoff;
      do_emergency = emergency && !emergency_bit_;  // the emergency bit toggles on its rising edge
      takeoff_bit_ = takeoff;
      emergency_bit_ = emergency;
    }
    std::lock_guard lock(vehicle_mutex_);
    vehicle_.advance_to(t);
    if (do_emergency) vehicle_.emergency(t);
    if (do_takeoff) vehicle_.takeoff(t);
    if (do_land) vehicle_.land(t);
  } else if (c.name == "PCMD" || c.name == "PCMD_MAG") {
    const WirePcmd wire{(c.args[0].integer & kPcmdProgressive) == 0, c.float_arg(1), c.float_arg(2), c.float_arg(3),
                        c.float_arg(4)};
    const bool finite = std::isfinite(wire.roll) && std::isfinite(wire.pitch) && std::isfinite(wire.gaz) &&
                        std::isfinite(wire.yaw);
    if (!finite) counters_.bad_input("at_pcmd_not_finite", t, "PCMD value is NaN or infinite");
    std::lock_guard lock(vehicle_mutex_);
    vehicle_.advance_to(t);
    vehicle_.move(finite ? move_from_wire(wire) : MoveCommand{}, wire.hover || !finite, t);
  } else if (c.name == "FTRIM") {
    std::lock_guard lock(vehicle_mutex_);
    vehicle_.flat_trim(t);
  } else if (c.name == "CONFIG") {
    if (c.args[0].is_string && c.args[1].is_string) {
      apply_config(c.args[0].text, c.args[1].text, t);
    } else {
      counters_.bad_input("at_config_not_strings", t, "AT*CONFIG arguments must be quoted strings");
    }
  } else if (c.name == "CALIB") {
    if (c.args[0].integer != 0) counters_.bad_input("at_calib_unknown_device", t, "AT*CALIB device is not 0");
  } else if (c.name == "CTRL") {
    if (c.args[0].integer == kCtrlAckConfig) {
      std::lock_guard lock(state_mutex_);
      config_ack_ = false;
    }
  }
  // COMWDG and CONFIG_IDS need nothing more here: every command resets the com watchdog.
}

void ArdroneEmulator::apply_config(const std::string& key, const std::string& value, Seconds t) {
  std::lock_guard lock(state_mutex_);
  if (key == "general:navdata_demo") {
    bootstrap_ = false;
    demo_ = value == "TRUE";
  } else if (key == "general:navdata_options") {
    char* end = nullptr;
    const unsigned long mask = std::strtoul(value.c_str(), &end, 10);
    if (end && *end == '\0' && !value.empty()) {
      options_mask_ = static_cast<std::uint32_t>(mask);
    } else {
      counters_.bad_input("config_bad_value", t, key + "=" + value);
    }
  } else if (key == "video:video_channel") {
    // Drone 2: 0 front, 1 bottom; node-ar-drone's README uses 2/3 (horizontal/vertical).
    if (value == "0" || value == "2") {
      pending_camera_ = CameraId::Front;
    } else if (value == "1" || value == "3") {
      pending_camera_ = CameraId::Bottom;
    } else {
      counters_.bad_input("config_bad_value", t, key + "=" + value);
    }
    camera_switch_t_ = t + settings_.camera_switch_delay_s;
  } else if (VideoBitrateControl::is_key(key)) {
    if (!bitrate_.apply(key, value)) counters_.bad_input("config_bad_value", t, key + "=" + value);
    streaming_bitrate_kbps_ = bitrate_.streaming_kbps();
  }
  config_ack_ = true;  // the firmware acknowledges every CONFIG (bit 6), the client clears it (CTRL 5)
  counters_.add("config_received");
}

// ---- navdata -----------------------------------------------------------------------------------

std::uint32_t ArdroneEmulator::state_bits(const VehicleTelemetry& tel, Seconds t) const {
  std::uint32_t s = state_mask(kStateVideoEnabled) | state_mask(2) | state_mask(7) | state_mask(23) |
                    (0xFu << 24);  // vision, camera ready, PIC ok, threads on
  if (tel.flying) s |= state_mask(kStateFlying);
  if (tel.battery_low) s |= state_mask(kStateBatteryLow);
  if (tel.motors_cut) s |= state_mask(kStateCutout);
  if (tel.emergency) s |= state_mask(kStateEmergency);
  if (bootstrap_) s |= state_mask(kStateBootstrap);
  if (demo_ && !bootstrap_) s |= state_mask(kStateNavdataDemo);
  if (config_ack_) s |= state_mask(kStateCommandAck);
  if (last_at_t_ < 0 || t - last_at_t_ > settings_.com_watchdog_s) s |= state_mask(kStateComWatchdog);
  return s;
}

// Fills the options of the current mode from the vehicle. Sensor options beyond the demo option use
// the drone's body axes (x forward, y right, z down), hence the sign flips on y and z.
void ArdroneEmulator::fill_packet(const VehicleTelemetry& tel, Seconds t) {
  packet_.clear();
  if (bootstrap_) return;  // header and checksum only
  const std::uint32_t mask = demo_ ? options_mask_ : 0xFFFFFFFu;
  for (const auto& spec : navdata_option_specs()) {
    if (mask & (1u << spec.tag)) packet_.add_option(spec.tag);
  }
  NavdataSample nav = tel.nav;
  nav.has_drone_time = false;  // the time option follows the mask, with the emulator's clock
  if (packet_.has(kTagDemo)) sample_to_packet(nav, packet_);
  if (packet_.has(kTagTime)) packet_.option(kTagTime).raw[0] = static_cast<double>(navdata_time_word(t));
  if (packet_.has(kTagRawMeasures)) {
    packet_.set(kTagRawMeasures, "vbat_raw", 11100.0 + 16.0 * tel.nav.battery_percent);  // 11.1..12.7 V LiPo
    packet_.set(kTagRawMeasures, "alt_temp_raw", std::round(tel.nav.altitude_m * 1e3));
  }
  if (packet_.has(kTagPhysMeasures)) {
    const double sign[3] = {1, -1, -1};
    for (std::size_t i = 0; i < 3; ++i) {
      packet_.set(kTagPhysMeasures, "phys_accs", sign[i] * tel.accel_body_mps2[static_cast<int>(i)] / kG * 1000.0, i);
      packet_.set(kTagPhysMeasures, "phys_gyros", sign[i] * tel.gyro_body_radps[static_cast<int>(i)] * kDegPerRad, i);
    }
  }
  if (packet_.has(kTagEulerAngles)) {
    packet_.set(kTagEulerAngles, "theta_a", -tel.nav.pitch_rad * kDegPerRad * 1000.0);
    packet_.set(kTagEulerAngles, "phi_a", tel.nav.roll_rad * kDegPerRad * 1000.0);
  }
  if (packet_.has(kTagAltitude)) {
    const double mm = std::round(tel.nav.altitude_m * 1e3);
    packet_.set(kTagAltitude, "altitude_vision", mm);
    packet_.set(kTagAltitude, "altitude_raw", mm);
    packet_.set(kTagAltitude, "altitude_vz", -tel.nav.vz_mps * 1e3);
  }
  if (packet_.has(kTagPressureRaw)) packet_.set(kTagPressureRaw, "pression_meas", std::round(tel.pressure_pa));
  if (packet_.has(kTagMagneto)) {
    packet_.set(kTagMagneto, "heading_fusion_unwrapped", -tel.magneto_heading_rad * kDegPerRad);
    packet_.set(kTagMagneto, "magneto_calibration_ok", 1);
  }
  if (packet_.has(kTagWindSpeed)) {
    packet_.set(kTagWindSpeed, "wind_speed", tel.wind_speed_mps);
    packet_.set(kTagWindSpeed, "wind_angle", tel.wind_angle_rad);
  }
  if (packet_.has(kTagWifi)) packet_.set(kTagWifi, "link_quality", std::round(tel.wifi_link_quality * 500.0));
  // kbit/s here; the firmware's unit for this field is not documented (to check on a real drone).
  if (packet_.has(kTagVideoStream)) packet_.set(kTagVideoStream, "desired_bitrate", streaming_bitrate_kbps_.load());
}

void ArdroneEmulator::navdata_loop() {
  std::vector<std::uint8_t> buffer(2048), datagram;
  datagram.reserve(4096);
  NavdataBuilder builder;
  Endpoint from;
  std::uint32_t sequence = 0;
  Seconds next_send = now();
  while (running_) {
    // Any datagram to port 5554 (the client's kick) sets where navdata goes.
    const Seconds wait = std::max(0.0, next_send - now());
    if (navdata_socket_.receive_from(buffer, from, wait) >= 0) {
      std::lock_guard lock(state_mutex_);
      if (!have_client_ || !(navdata_client_ == from)) {
        navdata_client_ = from;
        have_client_ = true;
        bootstrap_ = true;  // a new session starts in bootstrap mode
        sequence = 0;
        counters_.add("navdata_clients");
      }
      continue;
    }
    const Seconds t = now();
    if (t < next_send) continue;
    Endpoint to;
    double rate = 0;
    VehicleTelemetry tel;
    {
      std::lock_guard lock(vehicle_mutex_);
      vehicle_.advance_to(t);
      tel = vehicle_.telemetry();
    }
    {
      std::lock_guard lock(state_mutex_);
      rate = demo_ || bootstrap_ ? settings_.demo_rate_hz : settings_.full_rate_hz;
      next_send += 1.0 / rate;
      if (next_send < t) next_send = t + 1.0 / rate;  // overloaded: do not burst
      if (!have_client_) continue;
      to = navdata_client_;
      packet_.state = state_bits(tel, t);
      fill_packet(tel, t);
      if (camera_switch_t_ >= 0 && t >= camera_switch_t_) {
        camera_switch_t_ = -1;
        std::lock_guard vlock(vehicle_mutex_);
        vehicle_.select_camera(pending_camera_, t);
      }
    }
    packet_.sequence = ++sequence;
    builder.build(packet_, datagram);
    if (navdata_socket_.send_to(datagram, to)) counters_.add("navdata_sent");
  }
}

// ---- video -------------------------------------------------------------------------------------

void ArdroneEmulator::video_loop() {
  H264EncoderSettings es;
  es.fps = static_cast<int>(std::lround(settings_.video_fps));
  std::unique_ptr<H264Encoder> encoder;
  EncodedFrame encoded;
  PaveWriter writer;
  std::vector<std::uint8_t> stream;
  cv::Mat image;
  const Seconds period = 1.0 / settings_.video_fps;
  while (running_) {
    Socket client = video_listener_.accept(0.1);
    if (!client.valid()) continue;
    counters_.add("video_clients");
    es.bitrate_kbps = streaming_bitrate_kbps_;
    encoder = std::make_unique<H264Encoder>(es);  // a new client starts with an IDR
    std::uint32_t frame_number = 0;
    std::uint64_t position = 0;
    Seconds next = now();
    while (running_) {
      const Seconds t = now();
      if (t < next) {
        sleep_for(next - t);
        continue;
      }
      next = std::max(next + period, t);
      {
        std::lock_guard lock(vehicle_mutex_);
        vehicle_.advance_to(t);
        vehicle_.render(vehicle_.selected_camera(), image);
      }
      if (image.empty() || image.type() != CV_8UC3) {
        counters_.bad_input("vehicle_render_empty", t, "render() gave no BGR image");
        continue;
      }
      if (const int kbps = streaming_bitrate_kbps_; kbps != encoder->settings().bitrate_kbps) {
        encoder->set_bitrate_kbps(kbps);  // an AT*CONFIG changed it: from this frame on (an IDR)
        counters_.add("video_bitrate_changes");
      }
      if (!encoder->encode(image, encoded)) {
        counters_.add("video_encode_failed");
        continue;
      }
      PaveHeader h;
      h.frame_number = frame_number++;
      h.timestamp_ms = static_cast<std::uint32_t>(t * 1000.0);
      h.frame_type = static_cast<std::uint8_t>(encoded.keyframe ? PaveFrameType::Idr : PaveFrameType::P);
      h.header1_size = encoded.sps_size;
      h.header2_size = encoded.pps_size;
      h.display_width = static_cast<std::uint16_t>(image.cols);
      h.display_height = static_cast<std::uint16_t>(image.rows);
      h.encoded_width = static_cast<std::uint16_t>((image.cols + 15) / 16 * 16);
      h.encoded_height = static_cast<std::uint16_t>((image.rows + 15) / 16 * 16);
      h.stream_byte_position_lw = static_cast<std::uint32_t>(position);
      h.stream_byte_position_uw = static_cast<std::uint32_t>(position >> 32);
      position += encoded.data.size();
      stream.clear();
      writer.write(h, encoded.data, stream);
      if (!client.send_all(stream, 1.0)) {
        counters_.add("video_client_gone");
        break;
      }
      counters_.add("video_frames_sent");
    }
  }
}

}  // namespace labo::ardrone2
