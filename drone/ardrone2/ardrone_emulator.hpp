#pragma once
// ArdroneEmulator: speaks the AR.Drone 2.0 protocol on loopback over any EmulatedVehicle, in real
// time, so that ArdroneLink (or any AR.Drone client) can fly a simulated vehicle. It plays the
// drone's firmware side of the protocol: AT commands with the sequence rule, REF edges (take-off,
// land, emergency toggle), PCMD/PCMD_MAG, FTRIM, CONFIG + acknowledgement (state bit 6, CTRL 5),
// COMWDG and the com-watchdog bit; navdata in bootstrap, demo (15 Hz, general:navdata_options) or
// full mode (200 Hz, every option); PaVE/H.264 of vehicle.render() on TCP, with the camera switch
// (video:video_channel) applied after a delay, and the bit rate (video:bitrate_ctrl_mode,
// video:max_bitrate, video:bitrate) applied to the encoder from the next frame, reported in the
// video_stream option's desired_bitrate. Signs are converted at this edge (wire_signs.hpp).
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/log.hpp"
#include "drone/ardrone2/at_command.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/navdata_packet.hpp"
#include "drone/ardrone2/socket.hpp"
#include "drone/ardrone2/video_bitrate.hpp"
#include "drone/emulated_vehicle.hpp"

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::ardrone2 {

struct ArdroneEmulatorSettings {
  std::string bind_host = "127.0.0.1";
  int at_port = 5556;        // 0 picks a free port (tests)
  int navdata_port = 5554;
  int video_port = 5555;
  double demo_rate_hz = 15;
  double full_rate_hz = 200;
  double video_fps = 30;
  int video_bitrate_kbps = 1000;        // the firmware's video:max_bitrate until a client sets it
  Seconds camera_switch_delay_s = 1.0;  // a real switch takes more than 1 s
  Seconds com_watchdog_s = 0.05;        // no AT command for this long sets state bit 30
};

// Reads the "emulator" section; refuses unknown keys.
ArdroneEmulatorSettings read_ardrone_emulator_settings(const ConfigReader& section);

class ArdroneEmulator {
 public:
  ArdroneEmulator(EmulatedVehicle& vehicle, ArdroneEmulatorSettings settings, Logger logger);
  ~ArdroneEmulator();
  ArdroneEmulator(const ArdroneEmulator&) = delete;
  ArdroneEmulator& operator=(const ArdroneEmulator&) = delete;

  // Binds the three ports and starts the threads; throws when a port is taken.
  void start();
  void stop();
  int at_port() const { return at_port_; }
  int navdata_port() const { return navdata_port_; }
  int video_port() const { return video_port_; }
  // The bit rate the firmware streams at now (kbit/s), from the video:* keys received.
  int video_bitrate_kbps() const { return streaming_bitrate_kbps_.load(); }
  LinkStatistics statistics() const { return counters_.snapshot(); }
  // The vehicle's time: an emulator started over a vehicle that has already run (a restart on the
  // same ports) continues from vehicle.now(); a clock from 0 would stand the physics still until it
  // caught up (the vehicle's time is monotonic). Tested in "link: an emulator restarted over the
  // same vehicle continues its time".
  Seconds now() const { return time_origin_ + clock_.now(); }
  // Runs f(vehicle) under the lock the emulator's threads hold while they drive the vehicle, so
  // another thread (the server showing the simulated lab's ground truth) can read it safely. f must
  // be short: navdata and video wait for it.
  template <typename F>
  void with_vehicle(F&& f) {
    std::lock_guard lock(vehicle_mutex_);
    f(static_cast<const EmulatedVehicle&>(vehicle_));
  }
  // The same for a change to the vehicle's world while it runs (an instrument placed in the
  // simulated lab); f may take longer, the drone's streams pause meanwhile.
  template <typename F>
  void change_vehicle(F&& f) {
    std::lock_guard lock(vehicle_mutex_);
    f(vehicle_);
  }

 private:
  void at_loop();
  void navdata_loop();
  void video_loop();
  void handle_command(const ardrone2::AtCommand& command, Seconds t);
  void apply_config(const std::string& key, const std::string& value, Seconds t);
  std::uint32_t state_bits(const VehicleTelemetry& telemetry, Seconds t) const;
  void fill_packet(const VehicleTelemetry& telemetry, Seconds t);

  EmulatedVehicle& vehicle_;
  ArdroneEmulatorSettings settings_;
  Logger logger_;
  Seconds time_origin_ = 0;
  SteadyClock clock_;
  ardrone2::LinkCounters counters_;
  ardrone2::Socket at_socket_, navdata_socket_, video_listener_;
  int at_port_ = 0, navdata_port_ = 0, video_port_ = 0;

  std::mutex vehicle_mutex_;  // the vehicle is not thread-safe: every call under this lock
  // Firmware state, under state_mutex_.
  mutable std::mutex state_mutex_;
  bool bootstrap_ = true;
  bool demo_ = true;
  std::uint32_t options_mask_ = (1u << 0) | (1u << 16);  // DEMO | VISION_DETECT (65537)
  bool config_ack_ = false;
  bool takeoff_bit_ = false;
  bool emergency_bit_ = false;
  Seconds last_at_t_ = -1;
  bool have_client_ = false;
  ardrone2::Endpoint navdata_client_;
  CameraId pending_camera_ = CameraId::Front;
  Seconds camera_switch_t_ = -1;
  ardrone2::VideoBitrateControl bitrate_;
  std::atomic<int> streaming_bitrate_kbps_{0};  // what the encoder is asked for (video thread reads it)

  ardrone2::NavdataPacket packet_;  // navdata thread only
  std::atomic<bool> running_{false};
  std::thread at_thread_, navdata_thread_, video_thread_;
};

}  // namespace labo::ardrone2
