#pragma once
// What goes in and out of FlightStack: requests from users (missions and manual commands), the
// action to send to the drone each tick, and the status shown by the UI.
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "localization/fusion/localization_pipelines.hpp"
#include "core/time.hpp"
#include "drone/drone_link.hpp"

namespace labo::control {

enum class RequestKind {
  Takeoff,
  Land,
  Hover,           // cancel the mission, hold here
  Goto,            // x, y, z (m, world), yaw (rad)
  MoveBy,          // dx, dy, dz in the body frame, dyaw
  Inspect,         // instrument_id, hold_s (<= 0: config default), standoff_m (<= 0: config default)
  FindTeacher,     // person: the registered face to follow (none: the one followed so far)
  StopFaceFollow,
  ReturnHome,      // return to the platform and land
  EmergencyStop,
  SelectCamera,    // camera: what the drone streams while no mission runs (a mission chooses its own)
};
std::string to_string(RequestKind kind);

struct MissionRequest {
  RequestKind kind = RequestKind::Hover;
  std::string instrument_id;
  double hold_s = 0;
  double standoff_m = 0;
  Eigen::Vector4d target = Eigen::Vector4d::Zero();  // Goto: x, y, z, yaw; MoveBy: dx, dy, dz, dyaw
  CameraId camera = CameraId::Front;                 // SelectCamera
  std::shared_ptr<const face::PersonShape> person{};  // FindTeacher
};

struct CommandResult {
  bool accepted = false;
  std::string reason;  // why refused, or what was started
  static CommandResult ok(std::string what) { return {true, std::move(what)}; }
  static CommandResult refused(std::string why) { return {false, std::move(why)}; }
};

// The one action to send this tick.
struct FlightOutput {
  enum class Action { None, Move, Hover, Takeoff, Land, Emergency };
  Action action = Action::None;
  MoveCommand move;                      // when action == Move
  std::optional<CameraId> select_camera;  // switch the video channel (bottom camera in stage 5)
};
std::string to_string(FlightOutput::Action action);

enum class FlightPhase { Landed, TakingOff, Flying, Landing, Emergency };
std::string to_string(FlightPhase phase);

struct FlightStatus {
  Seconds t = 0;
  FlightPhase phase = FlightPhase::Landed;
  std::string mission;      // "idle", "inspect", "find_teacher", "return_home", "manual"
  std::string stage;        // e.g. "3 inspect: holding at standoff"
  int stage_index = 0;      // 1..stage_count, 0 when idle
  int stage_count = 0;
  std::string last_event;   // latest transition, refusal or safety action, for the UI log
  int missions_ended = 0;           // missions ended so far (a change: one has just ended)
  std::string last_mission_result;  // how the last one ended: "succeeded: ...", "failed: ...", "emergency stop", ...

  fusion::PoseEstimate pose;                       // fused, predicted to t
  std::optional<Eigen::Vector4d> desired;  // x, y, z, yaw the controller is driving to
  fusion::FeedbackSource source = fusion::FeedbackSource::DeadReckoning;
  std::string source_colour;
  MoveCommand last_command;

  double battery_percent = 0;
  double altitude_m = 0;
  LinkState link = LinkState::Disconnected;
  std::vector<std::string> safety_alerts;  // active: "link lost 2.1 s", "battery 18 %", ...

  fusion::SlamSummary slam;
  std::shared_ptr<const fusion::SlamPointsXy> slam_points;  // the map seen from above, refreshed once a second
  fusion::TargetObservation instrument;  // panel corners for the overlay
  fusion::TargetObservation platform;
  fusion::TargetObservation face;        // landmarks for the overlay
  std::optional<Eigen::Isometry3d> ground_truth_T_world_body;  // simulated runs only
};

}  // namespace labo::control
