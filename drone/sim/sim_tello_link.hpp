#pragma once
// SimTelloLink: the simulated lab seen through what a Tello (SDK 2.0) gives, in LOCKSTEP on a
// simulated clock: the lockstep model of `serve --drone tello` against `emulate --protocol tello`,
// for the bench's experiments (`labodrone-bench sim inspect --drone-model tello`). The same lab seed
// and link seed give the same flight bit for bit.
//
// Both ends are the real code, only the sockets and threads are gone:
//  - the drone is TelloFirmware (drone/tello/tello_firmware.hpp) over the SimulatedLab: it parses each
//    command datagram ("command", "takeoff", "rc a b c d", ...), answers as a Tello does, keeps its
//    15 s watchdog, and writes the state string with format_tello_state (whole degrees, dm/s, cm) at
//    `state_rate_hz`;
//  - the driver side is TelloLink's: TelloCommandChannel (one command in flight, timeouts, resends),
//    the sticks streamed as "rc a b c d" every `rc_interval_s` (MoveCommand x rc_limit_percent,
//    rounded: whole stick percents), SDK mode entered with "command" then "streamon", and every state
//    datagram through TelloStateReceiver (the parser, sample_from_state, TelloFlightPhase's
//    control_state), so the flight software reads exactly what TelloLink would hand it;
//  - video: after "streamon", the camera the firmware streams: the front one, or after "downvision 1"
//    (select_camera(Bottom) through TelloCameraSwitch, as TelloLink) the Tello EDU's downward camera,
//    grey, 320x240; a drone without it (`firmware.downvision` false) answers "error" and the frames
//    stay Front (`tello_downvision_refused`, then `tello_bottom_camera_unavailable`); with `h264` each
//    frame goes through the encoder, is cut into 1460-byte datagrams and is reassembled and decoded by
//    TelloVideoReceiver, as the emulator sends it and the link receives it;
//  - the network: each datagram delayed (SimLinkSettings: command_delay_s to the drone and for the
//    replies back, navdata_delay_s for the state, video_delay_s for the video; jitter_s), lost with
//    its channel's probability, and nothing during the lab's scheduled link outages;
//  - supervision: Connected while states arrive, Degraded after `degraded_after_s` of silence, Lost
//    after `lost_after_s`: SDK mode entered again, as TelloLink does.
// The vehicle under the firmware is the simulated lab's (drone/sim: the AR.Drone's plant and inner
// loops): a stick fraction flies as the AR.Drone's tilt fraction would (docs/tello.md, Known limits).
// A frame's pixels are valid only during on_video(). Single thread.
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "drone/ardrone2/link_counters.hpp"
#include "drone/sim/lockstep_link.hpp"
#include "drone/sim/lockstep_queue.hpp"
#include "drone/sim/sim_drone_link.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "drone/tello/tello_camera_switch.hpp"
#include "drone/tello/tello_command.hpp"
#include "drone/tello/tello_firmware.hpp"
#include "drone/tello/tello_receivers.hpp"

namespace labo::tello {
struct TelloConfig;
}  // namespace labo::tello

namespace labo::sim {


// What differs from the AR.Drone's lockstep link: the Tello's rates, its firmware and the driver's
// settings (from the `tello` section: sim_tello_settings()).
struct SimTelloSettings {
  double state_rate_hz = 10;                 // tello.emulator.state_rate_hz
  tello::TelloFirmwareSettings firmware;     // the drone's reply delay, watchdog, motion timeout
  tello::TelloCommandTiming timing;          // the driver's timeouts and resends (tello.link)
  Seconds rc_interval_s = 0.05;              // tello.link.rc_interval_s
  int rc_limit_percent = 100;                // tello.link.rc_limit_percent
  Seconds degraded_after_s = 0.5, lost_after_s = 2.0;
  bool video = true;                         // send streamon
  bool downvision = true;                    // tello.link.downvision: ask for the downward camera
  int video_gop = 30, video_bitrate_kbps = 2000;  // the encoder's, with SimLinkSettings::h264
};
SimTelloSettings sim_tello_settings(const tello::TelloConfig& tello);

class SimTelloLink final : public LockstepDroneLink {
 public:
  // The lab must outlive the link, which owns the lab's clock from now on. From `link`: the delays,
  // jitter, losses, video_fps, h264 and the seed; the rest of it is the AR.Drone's.
  SimTelloLink(SimulatedLab& lab, const SimLinkSettings& link, const SimTelloSettings& tello);
  ~SimTelloLink() override;
  SimTelloLink(const SimTelloLink&) = delete;
  SimTelloLink& operator=(const SimTelloLink&) = delete;

  void advance_to(Seconds t) override;
  Seconds now() const override { return now_; }
  // The drone's own counters (TelloFirmware: rc_received, watchdog_landings, unflown_commands, ...).
  const ardrone2::LinkCounters& drone_counters() const { return drone_counters_; }

  // DroneLink, as TelloLink does it.
  void set_listener(DroneLinkListener* listener) override { listener_ = listener; }
  void takeoff() override { push("takeoff"); }
  void land() override;
  void emergency() override;
  void flat_trim() override { counters_.add("tello_flat_trim_not_in_sdk"); }
  void move(const MoveCommand& command) override;
  void hover() override { sticks_ = tello::RcSticks{}; }
  void select_camera(CameraId camera) override;
  // The one key is "speed" (10-100 cm/s): sent as "speed N"; anything else throws std::invalid_argument.
  void set_config(const std::string& key, const std::string& value) override;
  LinkState state() const override { return state_; }
  LinkStatistics statistics() const override;

 private:
  enum class Channel { ToDrone, Reply, State, Video };
  struct DroneReply {
    std::string text;
    Seconds due_t = 0;
  };

  void push(std::string_view command);
  void driver_tick(Seconds t);
  void drone_tick(Seconds t);
  void state_tick(Seconds t);
  void video_tick(Seconds t);
  void send_to_drone(std::string_view text, Seconds t);
  void send_reply(std::string text, Seconds due_t);
  void deliver(Channel channel, std::size_t slot, Seconds t);
  void on_reply(std::string_view text, Seconds t);
  void finish(const tello::CommandOutcome& outcome, Seconds t);
  void enter_sdk_mode();
  void supervise(Seconds t);
  Seconds arrival(Seconds t, Seconds delay, Seconds& last_arrival);
  bool lost(double probability, Seconds t);
  std::size_t text_slot(std::string_view text);

  SimulatedLab& lab_;
  SimLinkSettings link_;
  SimTelloSettings tello_;
  DroneLinkListener* listener_ = nullptr;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  Seconds now_ = 0;

  // Driver side (TelloLink's parts).
  ardrone2::LinkCounters counters_;
  tello::TelloCommandChannel channel_;
  std::unique_ptr<tello::TelloStateReceiver> state_receiver_;
  std::unique_ptr<tello::TelloVideoReceiver> video_receiver_;
  tello::RcSticks sticks_;
  bool sdk_mode_ = false;
  tello::TelloCameraSwitch camera_switch_;
  LinkState state_ = LinkState::Disconnected;
  Seconds last_state_arrival_ = -1;
  std::string datagram_;
  // Drone side.
  ardrone2::LinkCounters drone_counters_;
  tello::TelloFirmware firmware_;
  std::vector<DroneReply> pending_replies_;
  std::string state_text_;
  std::uint32_t frame_number_ = 0;
  struct VideoEncoder;
  std::unique_ptr<VideoEncoder> encoder_;  // with h264, made at each new stream (an IDR first)
  cv::Mat rendered_;

  Seconds next_driver_ = 0, next_sticks_ = 0, next_state_ = 0, next_frame_ = 0;
  Seconds last_to_drone_ = 0, last_reply_ = 0, last_state_ = 0, last_video_ = 0;
  DeliveryQueue<Channel> queue_;
  SlotPool<std::string> texts_;                  // commands, replies, state strings in flight
  SlotPool<VideoFrame> frames_;                  // without h264
  SlotPool<std::vector<std::uint8_t>> units_;    // with h264: an access unit's bytes
};

}  // namespace labo::sim
