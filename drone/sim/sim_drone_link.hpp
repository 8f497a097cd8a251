#pragma once
// SimDroneLink: a DroneLink that flies a SimulatedLab in LOCKSTEP on a simulated clock, for runs of
// the whole flight software faster than real time (and slower, when vision needs it) with the same
// answer every time: the same lab seed and link seed give the same flight bit for bit.
//
// Usage (single thread; docs/sim.md):
//   SimulatedLab lab(...);                 // e.g. make_simulated_lab(lab_description, cameras, settings)
//   SimDroneLink link(lab, SimLinkSettings{});
//   link.set_listener(&flight_software);   // receives navdata, frames and link states
//   for (Seconds t = 0; t < 60; t += 0.02) {
//     link.advance_to(t);                  // delivers every event due by t, in time order
//     ... flight_software.tick(t) -> link.move(...) / takeoff() / land() ...
//   }
//
// What it models, as the real driver and drone would:
//  - the driver's AT loop: every 30 ms the current command (REF take-off/land/emergency bits, PCMD or
//    hover, pending CONFIG) goes out; it reaches the drone after `command_delay_s` (+ jitter) unless
//    lost, so the firmware's 2 s command timeout and REF edge detection behave as on the wire;
//  - navdata at 15 Hz (demo) or 200 Hz (full, with the drone's own time), delayed, jittered, lost;
//  - video at 30 fps from the selected camera (the switch takes effect `camera_switch_delay_s` after
//    the CONFIG arrives), delayed, jittered, lost; optionally through the real H.264 encoder and
//    decoder (drone/ardrone2/h264_codec.hpp) for the compression loss, the decoder waiting for an IDR
//    after a camera switch; the bit rate set as the driver sets it (video:bitrate_ctrl_mode,
//    video:max_bitrate and video:bitrate sent at connect, or later through set_config), applied when
//    the CONFIG reaches the drone; optionally both cameras every frame (not possible on a real AR.Drone 2.0,
//    for benchmarks and experiments); scheduled video dropouts of the lab send nothing;
//  - the lab's scheduled link outages: nothing gets through either way;
//  - link supervision: Connected while navdata arrives, Degraded after 0.5 s of silence, Lost after 2 s.
// Events keep their order per channel. A frame's pixels are valid only during on_video() (the link
// reuses its buffers): copy what you keep. Commands issued from inside a listener callback are
// stamped with that event's time.
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "drone/ardrone2/video_bitrate.hpp"
#include "drone/drone_link.hpp"
#include "drone/sim/lockstep_link.hpp"
#include "drone/sim/lockstep_queue.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo::ardrone2 {
class H264Encoder;
class H264Decoder;
}  // namespace labo::ardrone2

namespace labo::sim {


struct SimLinkSettings {
  bool full_navdata = false;         // 200 Hz with every option, else 15 Hz demo
  double demo_rate_hz = 15;
  double full_rate_hz = 200;
  double video_fps = 30;
  Seconds command_interval_s = 0.030;  // the driver's AT resend period
  Seconds navdata_delay_s = 0.040;   // drone to driver (estimation.navdata_delay_ms assumes 40)
  Seconds video_delay_s = 0.075;     // capture to decoded frame (estimation.video_delay_ms assumes 75)
  Seconds command_delay_s = 0.030;   // driver to drone
  Seconds jitter_s = 0.003;          // σ of a Gaussian added to every delay
  double navdata_loss = 0;           // probability per packet
  double video_loss = 0;             // per frame (the drone skips it)
  double command_loss = 0;           // per AT datagram
  bool h264 = false;                 // the real encoder and decoder in the loop
  // What the driver configures at connect (ArdroneLink's link.video_max_bitrate_kbps): the drone
  // streams at the firmware's 1000 kbit/s until those AT*CONFIGs arrive, then at this.
  int video_bitrate_kbps = 4000;
  bool both_cameras = false;         // every frame from both cameras
  Seconds camera_switch_delay_s = 1.0;
  Seconds degraded_after_s = 0.5;
  Seconds lost_after_s = 2.0;
  std::uint64_t seed = 1;
};

// Where the link's CPU time goes, with SimulatedLab::profile() for the rest.
struct SimLinkProfile {
  double codec_s = 0;  // H.264 encode + decode
  long encoded = 0;
};

class SimDroneLink final : public LockstepDroneLink {
 public:
  // The lab must outlive the link. The link owns the lab's clock from now on: drive it only through
  // advance_to().
  SimDroneLink(SimulatedLab& lab, SimLinkSettings settings);
  ~SimDroneLink() override;
  SimDroneLink(const SimDroneLink&) = delete;
  SimDroneLink& operator=(const SimDroneLink&) = delete;

  // Lockstep: runs the drone, the link and the listener's callbacks up to simulated time t.
  void advance_to(Seconds t) override;
  Seconds now() const override { return now_; }
  SimulatedLab& lab() { return lab_; }
  const SimLinkProfile& profile() const { return profile_; }
  // The bit rate the simulated drone streams at now (kbit/s).
  int video_bitrate_kbps() const { return drone_bitrate_.streaming_kbps(); }

  // DroneLink
  void set_listener(DroneLinkListener* listener) override { listener_ = listener; }
  void takeoff() override { takeoff_bit_ = true; }
  void land() override { takeoff_bit_ = false; }
  void emergency() override { emergency_ticks_ = 3; }  // the REF bit is a toggle: a few cycles, then cleared
  void flat_trim() override { flat_trim_ = true; }
  void move(const MoveCommand& command) override;
  void hover() override { hover_ = true; }
  void select_camera(CameraId camera) override { pending_camera_ = camera; }
  // general:navdata_demo, video:video_channel and the video bit-rate keys act as on the drone; other
  // keys (and bad values) are counted only.
  void set_config(const std::string& key, const std::string& value) override;
  LinkState state() const override { return state_; }
  LinkStatistics statistics() const override;

 private:
  // What one AT datagram carries to the drone.
  struct CommandPacket {
    bool takeoff_bit = false, emergency_bit = false, flat_trim = false, hover = true;
    MoveCommand move;
    std::optional<CameraId> camera;
    std::optional<bool> demo;
    std::optional<ardrone2::VideoBitrateControl> video_bitrate;  // the driver's requested state
  };
  enum class Channel { Command, Navdata, Video };
  struct Counters {
    std::uint64_t navdata_packets = 0, navdata_lost = 0, video_frames = 0, video_lost = 0, video_dropout = 0,
                  video_waiting_for_idr = 0, commands_sent = 0, commands_lost = 0, config_ignored = 0,
                  camera_switches = 0, video_bitrate_changes = 0;
  };
  struct VideoStream;  // one camera's H.264 encoder and decoder

  void send_commands(Seconds t);
  void generate_navdata(Seconds t);
  void generate_video(Seconds t);
  void render_frame(CameraId camera, Seconds arrival);
  void deliver(Channel channel, std::size_t slot, Seconds t);
  void apply_commands(const CommandPacket& p, Seconds t);
  void supervise(Seconds t);
  Seconds arrival(Seconds t, Seconds delay, Seconds& last_arrival);
  bool lost(double probability) { return probability > 0 && uniform_(rng_) < probability; }
  std::uint32_t state_bits(const VehicleTelemetry& tel) const;
  void schedule(Seconds t, Channel channel, std::size_t slot) { queue_.schedule(t, channel, slot); }

  SimulatedLab& lab_;
  SimLinkSettings settings_;
  DroneLinkListener* listener_ = nullptr;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  Seconds now_ = 0;

  // Driver side.
  bool takeoff_bit_ = false, flat_trim_ = false, hover_ = true;
  int emergency_ticks_ = 0;
  MoveCommand move_;
  std::optional<CameraId> pending_camera_;
  std::optional<bool> pending_demo_;
  ardrone2::VideoBitrateControl requested_bitrate_;
  bool pending_bitrate_ = false;
  LinkState state_ = LinkState::Disconnected;
  Seconds last_navdata_arrival_ = 0;
  // Drone side.
  bool drone_takeoff_bit_ = false, drone_emergency_bit_ = false;
  bool demo_;
  ardrone2::VideoBitrateControl drone_bitrate_;
  std::optional<CameraId> switching_to_;
  Seconds switch_at_ = 0;
  std::uint32_t sequence_ = 0, frame_number_ = 0;

  Seconds next_command_ = 0, next_navdata_ = 0, next_frame_ = 0;
  Seconds last_command_arrival_ = 0, last_navdata_arrival_sent_ = 0, last_video_arrival_ = 0;
  DeliveryQueue<Channel> queue_;
  SlotPool<CommandPacket> commands_;
  SlotPool<NavdataSample> navdata_;
  SlotPool<VideoFrame> frames_;
  std::vector<std::unique_ptr<VideoStream>> streams_;  // per camera, with h264
  cv::Mat rendered_;
  Counters counters_;
  SimLinkProfile profile_;
};

}  // namespace labo::sim
