#pragma once
// TelloEmulator: a Tello in SDK 2.0 mode on UDP, over any EmulatedVehicle, in real time, so that
// TelloLink (or any Tello client) can fly a simulated vehicle. Commands arrive on `command_port` and
// are answered to their sender (TelloFirmware plays the drone's side); once "command" has put it in
// SDK mode the state string goes to the sender's host at `client_state_port` every 1/state_rate_hz,
// and after "streamon" the streamed camera (the front one, or the downward one after "downvision 1" on an
// emulated Tello EDU) goes to `client_video_port` as raw H.264 (Baseline, an IDR
// every `video_gop` frames with SPS/PPS in band) cut into datagrams of 1460 bytes, the last of each
// frame shorter (as the drone does). Three threads: commands, state, video.
#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/log.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/socket.hpp"
#include "drone/emulated_vehicle.hpp"
#include "drone/tello/tello_firmware.hpp"

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::tello {

struct TelloEmulatorSettings {
  std::string bind_host = "127.0.0.1";
  int command_port = 8889;          // 0 picks a free port (tests)
  int client_state_port = 8890;     // on the host that sent "command"
  int client_video_port = 11111;
  double state_rate_hz = 10;
  double video_fps = 30;
  int video_width = 960, video_height = 720;
  int video_gop = 30;               // frames between IDRs
  int video_bitrate_kbps = 2000;
  tello::TelloFirmwareSettings firmware;
};

// Reads the "tello.emulator" section; refuses unknown keys.
TelloEmulatorSettings read_tello_emulator_settings(const ConfigReader& section);

class TelloEmulator {
 public:
  TelloEmulator(EmulatedVehicle& vehicle, TelloEmulatorSettings settings, Logger logger);
  ~TelloEmulator();
  TelloEmulator(const TelloEmulator&) = delete;
  TelloEmulator& operator=(const TelloEmulator&) = delete;

  // Binds the command port and starts the threads; throws when the port is taken.
  void start();
  void stop();
  int command_port() const { return command_port_; }
  // Where state and video go (a client whose ports are not the SDK's, e.g. a test's free ports).
  void set_client_ports(int state_port, int video_port);
  LinkStatistics statistics() const { return counters_.snapshot(); }
  // Runs f(vehicle) under the lock the emulator's threads hold while they drive the vehicle.
  template <typename F>
  void with_vehicle(F&& f) {
    std::lock_guard lock(vehicle_mutex_);
    f(static_cast<const EmulatedVehicle&>(vehicle_));
  }

 private:
  void command_loop();
  void state_loop();
  void video_loop();
  void send_due_replies(Seconds t);
  bool client(ardrone2::Endpoint& state_to, ardrone2::Endpoint& video_to) const;

  EmulatedVehicle& vehicle_;
  TelloEmulatorSettings settings_;
  Logger logger_;
  SteadyClock clock_;
  ardrone2::LinkCounters counters_;
  ardrone2::Socket command_socket_, stream_socket_;
  int command_port_ = 0;
  std::atomic<int> client_state_port_, client_video_port_;

  std::mutex vehicle_mutex_;  // the vehicle and the firmware: every call under this lock
  tello::TelloFirmware firmware_;
  struct PendingReply {
    std::string text;
    Seconds due_t = 0;
    ardrone2::Endpoint to;
  };
  std::vector<PendingReply> pending_;  // command thread only
  ardrone2::Endpoint last_sender_;     // command thread only: a motion command's reply goes there
  mutable std::mutex client_mutex_;
  bool have_client_ = false;
  ardrone2::Endpoint client_;          // the sender of "command"

  std::atomic<bool> running_{false};
  std::thread command_thread_, state_thread_, video_thread_;
};

}  // namespace labo::tello
