#pragma once
// DroneLink: what the rest of LaboDrone sees of a drone, real (AR.Drone 2.0 over Wi-Fi), emulated
// (the simulated lab speaking the same protocol on loopback) or replayed (a recorded flight).
// Commands go out; timestamped events come in through a DroneLinkListener. Units are SI inside:
// the driver converts the drone's millidegrees, mm and mm/s at its edge and keeps the raw values.
//
// Body frame: x forward, y left, z up; yaw counter-clockwise (core/frames.hpp).
#include <cstdint>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <span>
#include <string>

#include "core/time.hpp"

namespace labo {

enum class CameraId { Front = 0, Bottom = 1 };

// One navdata packet, in SI units. Angles in radians about the body axes (right-hand rule): roll about
// x (positive = right wing down), pitch about y (positive = nose down, the attitude of forward
// flight), yaw about z (positive = counter-clockwise).
struct NavdataSample {
  Seconds t = 0;               // receive time on the link's clock
  std::uint32_t sequence = 0;
  std::uint32_t state = 0;     // the 32 state bits (ArdroneState in drone/ardrone2/)
  int control_state = 0;       // major control state (namespace control_state below)
  double battery_percent = 0;
  double roll_rad = 0;
  double pitch_rad = 0;
  double yaw_rad = 0;
  double altitude_m = 0;       // ultrasound, to the surface below
  double vx_mps = 0;           // body-frame velocities from the bottom camera / observer
  double vy_mps = 0;
  double vz_mps = 0;
  bool has_drone_time = false;
  Seconds drone_time = 0;      // the drone's own clock (option `time`), when sent
};

// The firmware's major control states as NavdataSample::control_state carries them (the Tello link
// derives the same numbers from its state string).
namespace control_state {
constexpr int kLanded = 2;
constexpr int kFlying = 3;
constexpr int kHovering = 4;
constexpr int kTakingOff = 6;
constexpr int kLanding = 8;
// From 3 on (flying, hovering, test, taking off, go-to, landing, looping) the motors turn; 0-2
// (default, init, landed) they do not.
constexpr bool motors_on(int state) { return state >= kFlying; }
// The firmware follows the progressive commands only while flying or hovering; taking off and
// landing it flies its own manoeuvre.
constexpr bool follows_commands(int state) { return state == kFlying || state == kHovering; }
}  // namespace control_state

struct VideoFrame {
  Seconds t = 0;               // receive time of the frame's last byte
  CameraId camera = CameraId::Front;
  std::uint32_t frame_number = 0;
  cv::Mat bgr;                 // CV_8UC3
};

// One H.264 access unit as the drone sent it: Annex-B, the PaVE header stripped, all its slices. For
// passing the stream on without decoding it; `annexb` is valid only during the call.
struct EncodedVideo {
  Seconds t = 0;               // receive time of the unit's last byte (the decoded frame's t)
  CameraId camera = CameraId::Front;
  std::uint32_t frame_number = 0;
  bool keyframe = false;       // an IDR (with SPS and PPS): a decoder can start here
  int width = 0, height = 0;   // display size
  std::span<const std::uint8_t> annexb;
};

enum class LinkState { Disconnected, Connecting, Connected, Degraded, Lost };
std::string to_string(LinkState state);

// Counts by kind: packets, bytes, drops and every kind of bad input, for the UI and /metrics.
struct LinkStatistics {
  std::map<std::string, std::uint64_t> counters;
  double navdata_rate_hz = 0;
  double video_fps = 0;
};

// Normalized PCMD: each in [-1, 1], fractions of euler_angle_max, control_vz_max, control_yaw.
// Signs in LaboDrone's body frame: roll > 0 tilts to the right (moves right), pitch > 0 tilts the
// nose down (moves forward), gaz > 0 climbs, yaw_rate > 0 turns counter-clockwise. The driver maps
// them to the AR.Drone's own signs on the wire.
struct MoveCommand {
  double roll = 0;
  double pitch = 0;
  double gaz = 0;
  double yaw_rate = 0;
};

class DroneLinkListener {
 public:
  virtual ~DroneLinkListener() = default;
  virtual void on_navdata(const NavdataSample& sample) = 0;
  virtual void on_video(const VideoFrame& frame) = 0;
  // The frame's access unit before it is decoded (links that receive H.264), from an IDR on after
  // every reset of the stream; called before on_video for the same frame.
  virtual void on_encoded_video(const EncodedVideo&) {}
  virtual void on_link_state(LinkState state, Seconds t) = 0;
};

class DroneLink {
 public:
  virtual ~DroneLink() = default;
  virtual void set_listener(DroneLinkListener* listener) = 0;

  virtual void takeoff() = 0;
  virtual void land() = 0;
  virtual void emergency() = 0;
  virtual void flat_trim() = 0;
  // Values outside [-1, 1] are clipped; non-finite values become a hover.
  virtual void move(const MoveCommand& command) = 0;
  virtual void hover() = 0;
  virtual void select_camera(CameraId camera) = 0;
  virtual void set_config(const std::string& key, const std::string& value) = 0;

  virtual LinkState state() const = 0;
  virtual LinkStatistics statistics() const = 0;
};

}  // namespace labo
