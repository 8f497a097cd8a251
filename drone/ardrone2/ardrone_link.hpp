#pragma once
// ArdroneLink: the real AR.Drone 2.0 driver (AT commands on UDP 5556, navdata on UDP 5554, video on
// TCP 5555), behind DroneLink. Three threads: control (the 30 ms AT loop, config handshake, COMWDG,
// link supervision), navdata (receive + parse) and video (connect, demux, decode, reconnect). Events
// reach the listener from those threads, one at a time (never concurrently). SteadyClock times.
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/log.hpp"
#include "drone/ardrone2/at_command.hpp"
#include "drone/ardrone2/config_handshake.hpp"
#include "drone/ardrone2/drone_restart_watch.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/link_receiver.hpp"
#include "drone/ardrone2/socket.hpp"
#include "drone/ardrone2/video_bitrate.hpp"
#include "drone/drone_link.hpp"
#include "drone/link_status.hpp"
#include "drone/replay/recording.hpp"

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::ardrone2 {

struct ArdroneLinkSettings {
  std::string host = "192.168.1.1";
  int at_port = 5556;
  int navdata_port = 5554;
  int video_port = 5555;
  Seconds command_interval_s = 0.030;   // AT resend period (guide: every 30 ms)
  Seconds degraded_after_s = 0.5;       // navdata silence -> Degraded
  Seconds lost_after_s = 2.0;           // navdata silence -> Lost (then reconnect)
  Seconds config_ack_timeout_s = 0.5;   // resend a CONFIG not acknowledged in this time
  bool full_navdata = false;            // false: navdata_demo at 15 Hz; true: all options at 200 Hz
  bool video = true;
  // Sent at every connect as video:bitrate_ctrl_mode 0 (VBC_MODE_DISABLED: the stream held at
  // video:max_bitrate) and video:max_bitrate (the firmware's default is 1000). 4000: ardrone_autonomy's
  // choice for the AR.Drone 2.0, and the pose of a panel at 2-3 m needs it (docs/planar.md).
  int video_max_bitrate_kbps = 4000;
  std::filesystem::path recording;      // empty: no recording
};


// Reads the "link" section (keys as above; see docs/ardrone2.md); refuses unknown keys.
ArdroneLinkSettings read_ardrone_link_settings(const ConfigReader& section);

class ArdroneLink final : public DroneLink {
 public:
  // `clock` stamps every event and record (it must be thread-safe and outlive the link); by default
  // the link's own SteadyClock.
  ArdroneLink(ArdroneLinkSettings settings, Logger logger, const Clock* clock = nullptr);
  ~ArdroneLink() override;
  ArdroneLink(const ArdroneLink&) = delete;
  ArdroneLink& operator=(const ArdroneLink&) = delete;

  // Starts the threads (the link then goes Connecting). Throws when sockets cannot be opened.
  void start();
  void stop();
  // The local UDP port navdata arrives on (after start(); the drone streams to whoever kicks it).
  int navdata_local_port() const { return navdata_socket_.local_port(); }

  void set_listener(DroneLinkListener* listener) override;
  void takeoff() override;
  void land() override;
  void emergency() override;
  void flat_trim() override;
  void move(const MoveCommand& command) override;
  void hover() override;
  void select_camera(CameraId camera) override;
  void set_config(const std::string& key, const std::string& value) override;
  LinkState state() const override;
  // The bit rate asked of the drone from now on (video_bitrate_configs) and at every reconnection;
  // throws std::invalid_argument outside kMinVideoBitrateKbps..kMaxVideoBitrateKbps.
  void set_video_bitrate_kbps(int kbps);
  int video_bitrate_kbps() const;
  // AR.Drone-specific: AT*CALIB for the magnetometer (only honoured in flight).
  void calibrate_magnetometer();
  LinkStatistics statistics() const override;
  // The recording's bytes so far (RecordingWriter::bytes_written; 0 without link.recording). After
  // stop() the file is flushed and holds exactly this many.
  std::uint64_t recorded_bytes() const { return recorder_ ? recorder_->bytes_written() : 0; }

 private:
  void control_loop();
  void navdata_loop();
  void video_loop();
  void send_commands(Seconds t);
  void run_config_handshake(Seconds t, std::uint32_t state);
  void supervise(Seconds t);
  void set_state(LinkState s, Seconds t);
  void on_navdata(const NavdataSample& sample, const ardrone2::NavdataPacket& packet);
  void on_video(const VideoFrame& frame);
  void queue_startup_config();
  // A reconnection (the link was lost) or a drone that restarted under it: AT sequence from 1, the
  // start-up configuration again, the video connection reopened.
  void redo_startup(const char* counter);
  void record(replay::RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes);

  ArdroneLinkSettings settings_;
  Logger logger_;
  SteadyClock own_clock_;
  const Clock* clock_;
  ardrone2::LinkCounters counters_;
  LinkStatus status_;
  std::unique_ptr<replay::RecordingWriter> recorder_;
  ardrone2::Endpoint at_endpoint_, navdata_endpoint_, video_endpoint_;
  ardrone2::Socket at_socket_, navdata_socket_;

  mutable std::mutex listener_mutex_;  // events never reach the listener concurrently
  DroneLinkListener* listener_ = nullptr;

  // Command state shared with the control thread.
  mutable std::mutex command_mutex_;
  bool takeoff_ = false;
  int emergency_cycles_ = 0;  // REF emergency bit is a toggle: sent for a few cycles, then cleared
  bool flat_trim_ = false;
  bool calibrate_ = false;
  ardrone2::WirePcmd pcmd_;
  ardrone2::ConfigHandshake configs_;
  bool reset_sequence_ = true;
  CameraId requested_camera_ = CameraId::Front;
  int video_bitrate_kbps_;  // sent at every connect; settings_.video_max_bitrate_kbps until changed

  std::atomic<std::uint32_t> drone_state_{0};
  std::atomic<double> last_navdata_t_{-1.0};
  std::atomic<bool> reset_video_{false};          // reopen the TCP connection
  std::atomic<bool> reset_video_decoder_{false};  // camera switched: wait for the next IDR
  std::atomic<CameraId> active_camera_{CameraId::Front};
  ardrone2::DroneRestartWatch restart_watch_;          // navdata thread only
  std::atomic<bool> restart_watch_reset_{false};      // the start-up config was queued: restart_watch_ waits for it

  ardrone2::AtCommandEncoder encoder_;  // control thread only
  std::string at_buffer_;
  std::atomic<bool> running_{false};
  std::thread control_thread_, navdata_thread_, video_thread_;
  std::unique_ptr<ardrone2::NavdataReceiver> navdata_receiver_;
  std::unique_ptr<ardrone2::VideoReceiver> video_receiver_;
};

}  // namespace labo::ardrone2
