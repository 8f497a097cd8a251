#pragma once
// Which requests FlightStack accepts, and why it refuses the others: unknown instrument, a second
// mission while one runs, a goto outside the geofence, a standoff below the safe minimum, NaN or
// infinite values, commands that need flight while the drone is landed, take-off on a low battery or
// without a link. Pure: it decides, FlightStack executes.
#include "control/control_config.hpp"
#include "control/flight_types.hpp"
#include "control/geofence.hpp"
#include "localization/fusion/lab_geometry.hpp"

namespace labo::control {

struct RequestContext {
  FlightPhase phase = FlightPhase::Landed;
  std::string running_mission;  // empty when none
  std::string running_stage;
  bool mission_accepts_stop_face_follow = false;
  LinkState link = LinkState::Connected;
  double battery_percent = 100;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0;
  Eigen::Vector4d current_target = Eigen::Vector4d::Zero();  // MoveBy is relative to the target
  bool has_target = false;
  double unobserved_flight_s = 0;  // fusion::PoseEstimate's: > 0, the drone's place is not confirmed
};

CommandResult check_request(const MissionRequest& request, const RequestContext& ctx, const fusion::LabGeometry& lab,
                            const Geofence& fence, const ControlConfig& config);

}  // namespace labo::control
