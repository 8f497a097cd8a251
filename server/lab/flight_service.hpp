#pragma once
// What the web layer sees of the flying side: mission requests in, acknowledgements, telemetry,
// annotated video frames and mission events out. FlightRuntime (server/flight_runtime) implements it
// around a DroneLink and control's FlightStack; tests implement it with a scripted double. Nothing
// here knows about HTTP or JSON.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drone/drone_link.hpp"
#include "drone/lab/lab_description.hpp"
#include "localization/face/person_shape.hpp"
#include "localization/fusion/slam_points_top_down.hpp"
#include "server/lab/stage_timeline.hpp"
#include "server/runtime/runtime_timing.hpp"
#include "server/video/rendition.hpp"

namespace labo::server {

// Stop ends whatever runs and lands (the drone holds, then descends): anyone watching may send it.
// EmergencyStop cuts the motors: only the controller, a teacher or an admin.
// Jog moves by a small step (body frame) while no mission runs, inside the geofence.
enum class MissionCommandKind {
  Takeoff, Inspect, FindTeacher, StopFaceFollow, ReturnHome, Land, Stop, EmergencyStop, SelectCamera, Jog
};
std::string to_string(MissionCommandKind kind);
std::optional<MissionCommandKind> parse_mission_command(const std::string& text);

struct MissionCommand {
  MissionCommandKind kind = MissionCommandKind::Land;
  std::string instrument;  // Inspect: the instrument's id
  double hold_s = 10;      // Inspect: how long to hold in front of the panel
  CameraId camera = CameraId::Front;  // SelectCamera: what the drone streams while no mission runs
  // Jog: metres forward, left, up and radians counter-clockwise, from where the drone is held now.
  double dx_m = 0, dy_m = 0, dz_m = 0, dyaw_rad = 0;
  // FindTeacher: the registered person to follow, attached by the lab (the teacher's choice); none:
  // the one the flight software followed so far.
  std::shared_ptr<const face::PersonShape> person{};
};

struct CommandVerdict {
  bool accepted = false;
  std::string reason;  // why it was rejected (or a note when accepted)
};

struct PoseXyzYaw {
  double x_m = 0, y_m = 0, z_m = 0, yaw_rad = 0;
};

// The localization source of the pose estimate, with the paper's colour code (Figs 5-9, 12).
enum class PoseSource { Slam, Homography, Face, DeadReckoning, VisionLost };
std::string to_string(PoseSource source);
std::string colour_of(PoseSource source);  // "#00b000" green SLAM, blue homography, ...

struct FlightTelemetry {
  double t_unix_s = 0;
  std::string mission = "idle";
  std::string stage;
  MissionTimeline timeline;  // the current or last mission's stages (stage_timeline.hpp)
  PoseXyzYaw pose;
  std::optional<PoseXyzYaw> desired;
  std::optional<PoseXyzYaw> ground_truth;  // simulated lab only
  PoseSource source = PoseSource::DeadReckoning;
  double source_quality = 0;
  double battery_percent = 0;
  double altitude_m = 0;
  // Seconds of flight the navdata did not see since the last fix on the lab (fusion::PoseEstimate's):
  // > 0, the drone's place is not confirmed and a landed drone takes no mission until it is set on
  // its platform (set_down_on_platform).
  double unobserved_flight_s = 0;
  double link_quality = 0;  // 0..1
  std::string link_state = "disconnected";
  bool flying = false;
  std::string slam_state;
  int slam_keyframes = 0;
  double slam_map_mib = 0;  // the SLAM map's memory (bounded by slam.max_keyframes)
  // The SLAM map seen from above (world m, bounded, decimated), refreshed about once a second; the
  // clients get it in its own message when its revision changes (lab_messages.hpp).
  std::shared_ptr<const fusion::SlamPointsXy> slam_points;
  std::optional<std::pair<double, double>> teacher_xy;
  double video_fps = 0;
};

// An encoded frame ready for the wire: a 24-byte header then the JPEG (see video/frame_header.hpp).
struct WireFrame {
  std::uint32_t frame_number = 0;
  double capture_unix_ms = 0;
  CameraId camera = CameraId::Front;
  std::shared_ptr<const std::string> wire;  // shared by every client: built once per frame
};

// One H.264 access unit ready for the wire (video/access_unit_wire.hpp), with its frame's overlay
// geometry (JSON, video/overlay_geometry.hpp); both built once and shared by every H.264 viewer.
struct WireAccessUnit {
  std::uint32_t frame_number = 0;
  double capture_unix_ms = 0;
  CameraId camera = CameraId::Front;
  bool keyframe = false;
  Rendition rendition = Rendition::Source;
  std::shared_ptr<const std::string> wire;
  std::shared_ptr<const std::string> geometry;
};

struct FlightEvent {
  std::string kind;     // "stage", "mission", "error", "link"
  std::string mission;  // mission name
  std::string stage;
  std::string message;
};

class FlightEventSink {
 public:
  virtual ~FlightEventSink() = default;
  // Called from the runtime's threads: implementations hand off quickly (post, never block).
  virtual void on_frame(const WireFrame& frame) = 0;
  // Every access unit of the drone's stream, in order, from an IDR on (never skipped here: a viewer
  // that cannot keep up skips to the next IDR on its own).
  virtual void on_access_unit(const WireAccessUnit&) {}
  // The instrument reading view (video/panel_reading_view.hpp), a few times a second while a panel
  // is tracked.
  virtual void on_reading_view(std::shared_ptr<const std::string>) {}
  virtual void on_flight_event(const FlightEvent& event) = 0;
  // Whether anyone watches each path now: the runtime skips the JPEG encode, the access units and
  // their geometry, or the reading view, that nobody would receive.
  virtual bool wants_jpeg() const { return true; }
  virtual bool wants_access_units() const { return false; }
  virtual bool wants_reading_view() const { return false; }
  // Whether an H.264 viewer needs the shared low rendition (video/low_rendition.hpp): its encoder runs
  // only then. A viewer that just moved to it asks for an IDR, taken (and cleared) by the encoder.
  virtual bool wants_low_rendition() const { return false; }
  virtual bool take_low_keyframe_request() { return false; }
};

// What the drone's video offers beyond its front camera's stream, for the page and the admin; the
// drone backend knows it (server/runtime/drone_backend.cpp).
struct VideoCapabilities {
  std::string drone;                // "AR.Drone 2.0", "Tello", "recording", ...
  bool bottom_camera = false;       // a second camera the link can switch the stream to
  std::string no_bottom_camera;     // why not, when not (the refusal's words)
  bool adjustable_bitrate = false;  // the link can ask the drone for a bit rate
  int bitrate_kbps = 0;             // what it asks for now (0: nothing)
  int min_bitrate_kbps = 0, max_bitrate_kbps = 0;
};

struct InstrumentSummary {
  std::string id, name;
  double width_m = 0, height_m = 0;
  double x_m = 0, y_m = 0;  // panel centre in the world, for the map
  double facing_rad = 0;    // the direction the panel faces (its viewer stands that way), about z
};

// The lab as its file states it, for the page's map: the room's walls, the benches and the base with
// its platform, seen from above. What a real deployment knows, never the simulated lab's true
// placements. (The instruments come apart: InstrumentSummary.)
struct LabFootprint {
  std::string id;
  double min_x_m = 0, min_y_m = 0, max_x_m = 0, max_y_m = 0;
  double min_z_m = 0, max_z_m = 0;  // its height (a bench's top), to check a placement against
};
struct LabOutline {
  bool known = false;  // false: the flight service knows no lab file
  LabFootprint room;
  std::vector<LabFootprint> benches;
  LabFootprint platform;
  double base_x_m = 0, base_y_m = 0, base_yaw_rad = 0;
};

class FlightService {
 public:
  virtual ~FlightService() = default;
  virtual void set_sink(FlightEventSink* sink) = 0;
  // Thread-safe; an emergency stop acts before this returns.
  virtual CommandVerdict request(const MissionCommand& command) = 0;
  virtual FlightTelemetry telemetry() const = 0;
  virtual std::vector<InstrumentSummary> instruments() const = 0;
  virtual LabOutline lab_outline() const { return {}; }
  // Places an instrument in the lab, live: inspectable once accepted (and, in the simulated lab, its
  // panel drawn where `spec` says). Refused with the reason: an id the lab has, a panel outside the
  // room, a template the vision cannot use, or a flight service that cannot.
  virtual CommandVerdict add_instrument(const lab::InstrumentSpec& spec) {
    return {false, "instrument '" + spec.id + "': this flight service cannot add instruments"};
  }
  // No longer inspectable (refused while a mission inspects it). The simulated lab keeps drawing its
  // panel, as a real lab keeps the instrument on its bench.
  virtual CommandVerdict remove_instrument(const std::string& id) {
    return {false, "instrument '" + id + "': this flight service cannot remove instruments"};
  }
  // Someone set the drone on its charging platform: its place is the base's again, confirmed.
  // Refused (with the reason) while it flies or a mission runs.
  virtual CommandVerdict set_down_on_platform() { return {false, "this flight service cannot be told where the drone is"}; }
  // Graceful shutdown: land (waiting up to timeout_s for touchdown), then stop the threads.
  virtual void land_and_stop(double timeout_s) = 0;
  // How the flight thread has kept time (control ticks, vision latency, frames); empty without one.
  virtual RuntimeTimingSummary timing() const { return {}; }
  // The drone's video: its cameras and the bit rate the link asks of it.
  virtual VideoCapabilities video_capabilities() const { return {}; }
  // Refused (with the reason) outside video_capabilities()'s range or when the link cannot.
  virtual CommandVerdict set_video_bitrate(int kbps) {
    (void)kbps;
    return {false, "this flight service has no drone link"};
  }
};

}  // namespace labo::server
