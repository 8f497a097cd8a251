#pragma once
// TelloLink: a Ryze/DJI Tello or Tello EDU in SDK 2.0 mode behind DroneLink (docs/tello.md). Text
// commands to the drone's UDP 8889 with their replies (TelloCommandChannel: one in flight, timeouts,
// resends), the state string on our UDP 8890 (~10 Hz), raw H.264 on our UDP 11111. Three threads:
// control (commands and replies, the sticks streamed as "rc a b c d" every rc_interval_s, which also
// keeps the drone's 15 s no-command watchdog from landing it, link supervision), state (receive +
// parse) and video (receive, reassemble, decode). Events reach the listener from those threads, one at
// a time. SteadyClock times unless a clock is given.
//
// The bottom camera is the Tello EDU's downward camera: select_camera() sends "downvision 1|0"
// (TelloCameraSwitch) and frames of the downward camera's size come labelled Bottom. What the drone
// cannot do is refused in the open, never faked: a Tello that answers "downvision 1" with "error" (or
// not at all), or a link configured without `downvision`, streams the front camera only
// (select_camera(Bottom) is counted and logged, frames stay Front: the mission's platform search then
// lands at the estimated base when it times out, docs/tello.md "Landing without a bottom camera");
// and it has no flat trim in SDK mode.
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/log.hpp"
#include "drone/ardrone2/link_counters.hpp"
#include "drone/ardrone2/socket.hpp"
#include "drone/drone_link.hpp"
#include "drone/link_status.hpp"
#include "drone/replay/recording.hpp"
#include "drone/tello/tello_camera_switch.hpp"
#include "drone/tello/tello_command.hpp"
#include "drone/tello/tello_receivers.hpp"
#include "drone/tello/tello_wire.hpp"

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::tello {

struct TelloLinkSettings {
  std::string host = "192.168.10.1";  // the Tello's own access point
  int command_port = 8889;            // the drone's
  int state_port = 8890;              // ours, where the drone sends its state (0: a free port)
  int video_port = 11111;             // ours, where it sends the video (0: a free port)
  Seconds reply_timeout_s = 1.0;      // command, streamon, reads, settings, emergency
  Seconds motion_timeout_s = 10.0;    // takeoff, land, moves: answered once done
  int command_retries = 2;            // resends of commands that may be repeated
  Seconds rc_interval_s = 0.05;       // the sticks' period (the drone lands after 15 s without a command)
  int rc_limit_percent = 100;         // stick deflection at a MoveCommand value of 1 (1-100)
  Seconds degraded_after_s = 0.5;     // state silence -> Degraded
  Seconds lost_after_s = 2.0;         // state silence -> Lost (then SDK mode is entered again)
  bool video = true;                  // send "streamon" after "command"
  bool downvision = true;             // ask for the downward camera ("downvision 1") when the bottom camera is selected
  std::filesystem::path recording;    // empty: no recording
};

// Reads the "tello.link" section (keys as above); refuses unknown keys.
TelloLinkSettings read_tello_link_settings(const ConfigReader& section);

class TelloLink final : public DroneLink {
 public:
  TelloLink(TelloLinkSettings settings, Logger logger, const Clock* clock = nullptr);
  ~TelloLink() override;
  TelloLink(const TelloLink&) = delete;
  TelloLink& operator=(const TelloLink&) = delete;

  // Binds our three UDP sockets (throws naming the port when one is taken); start() does it too.
  // Separate so that a test can tell an emulator our ports before anything is sent.
  void open();
  int state_port() const { return state_socket_.local_port(); }
  int video_port() const { return video_socket_.local_port(); }
  // Starts the threads: the link goes Connecting and sends "command" until the drone answers.
  void start();
  void stop();

  void set_listener(DroneLinkListener* listener) override;
  void takeoff() override;
  void land() override;
  void emergency() override;
  void flat_trim() override;
  void move(const MoveCommand& command) override;
  void hover() override;
  void select_camera(CameraId camera) override;
  // "speed" (10-100 cm/s, the speed of the SDK's move commands) is the one key; others throw
  // std::invalid_argument naming it.
  void set_config(const std::string& key, const std::string& value) override;
  LinkState state() const override;
  LinkStatistics statistics() const override;

  // Queues any SDK command (e.g. "battery?", "cw 90"); false when invalid or the queue is full.
  bool send_command(const std::string& command);

 private:
  void control_loop();
  void state_loop();
  void video_loop();
  void send_command_tick(Seconds t);
  void send_sticks(Seconds t);
  void receive_replies(Seconds wait_s);
  void finish(const tello::CommandOutcome& outcome, Seconds t);
  void refuse_bottom_camera(Seconds t, std::string_view why);
  void supervise(Seconds t);
  void set_state(LinkState s, Seconds t);
  void enter_sdk_mode();
  void send_datagram(replay::RecordChannel channel, std::string_view text, Seconds t);
  void record(replay::RecordChannel channel, Seconds t, std::span<const std::uint8_t> bytes);
  bool from_drone(const ardrone2::Endpoint& from, Seconds t, std::string_view kind);

  TelloLinkSettings settings_;
  Logger logger_;
  SteadyClock own_clock_;
  const Clock* clock_;
  ardrone2::LinkCounters counters_;
  LinkStatus status_;
  RateLimiter refusals_{1.0};  // what the Tello cannot do, logged at most once a second per kind
  std::unique_ptr<replay::RecordingWriter> recorder_;
  ardrone2::Endpoint command_endpoint_;
  ardrone2::Socket command_socket_, state_socket_, video_socket_;

  mutable std::mutex listener_mutex_;  // events never reach the listener concurrently
  DroneLinkListener* listener_ = nullptr;

  mutable std::mutex command_mutex_;   // the channel and the sticks, shared with the control thread
  tello::TelloCommandChannel channel_;
  tello::RcSticks sticks_;
  bool sdk_mode_ = false;              // "command" answered ok since the last connect
  tello::TelloCameraSwitch camera_switch_;

  // Orders what the flight phase learns with what the recording holds (a command sent, a reply, a
  // state string), so that a replay derives the same control_state for every sample.
  std::mutex session_mutex_;
  std::atomic<double> last_state_t_{-1.0};
  std::atomic<bool> reset_video_{false};

  std::string datagram_;  // control thread only: the text being sent
  std::atomic<bool> running_{false};
  std::thread control_thread_, state_thread_, video_thread_;
  std::unique_ptr<tello::TelloStateReceiver> state_receiver_;
  std::unique_ptr<tello::TelloVideoReceiver> video_receiver_;
};

}  // namespace labo::tello
