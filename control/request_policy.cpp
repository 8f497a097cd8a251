#include "control/request_policy.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

#include "control/mission.hpp"

namespace labo::control {

namespace {

bool airborne(FlightPhase p) { return p == FlightPhase::Flying || p == FlightPhase::TakingOff; }

std::string known_instruments(const fusion::LabGeometry& lab) {
  std::string s;
  for (const auto& i : lab.instruments) s += (s.empty() ? "" : ", ") + i.id;
  return s.empty() ? "none configured" : s;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

// The world position a Goto or MoveBy would fly to.
Eigen::Vector3d destination(const MissionRequest& r, const RequestContext& ctx) {
  if (r.kind == RequestKind::Goto) return r.target.head<3>();
  const Eigen::Vector3d from = ctx.has_target ? Eigen::Vector3d(ctx.current_target.head<3>()) : ctx.position;
  const double yaw = ctx.has_target ? ctx.current_target[3] : ctx.yaw;
  // MoveBy is in the body frame: dx forward, dy left.
  const Eigen::Vector2d d(std::cos(yaw) * r.target.x() - std::sin(yaw) * r.target.y(),
                          std::sin(yaw) * r.target.x() + std::cos(yaw) * r.target.y());
  return from + Eigen::Vector3d(d.x(), d.y(), r.target.z());
}

// A landed drone whose estimate lies beyond the walls has lost its pose (a tumble, a long link cut
// dead reckoned wrong): a mission flown from there flies at full speed towards a place it is not at.
std::optional<CommandResult> refuse_lost_pose(const std::string& what, const RequestContext& ctx, const Geofence& fence,
                                              const ControlConfig& config) {
  if (airborne(ctx.phase)) return std::nullopt;  // in flight the safety monitor lands it
  if (ctx.unobserved_flight_s > 0) {
    // Landed after a silence in flight, with no fix since: the estimate is where the bridge put it,
    // and a mission from there flies a place the drone is not at (a soak's crash: 1.4 m off).
    return CommandResult::refused(what + ": the drone's place is not confirmed: the navdata stopped for " +
                                  number(ctx.unobserved_flight_s) +
                                  " s in flight and no fix on the lab has come since. Set the drone on its platform "
                                  "and confirm it (an admin: POST /api/drone/set-down) before it flies again");
  }
  const double outside_m = fence.horizontal_distance_outside_m(ctx.position);
  const double limit_m = config.safety.pose_lost_outside_fence_m;
  if (limit_m <= 0 || outside_m <= limit_m) return std::nullopt;
  return CommandResult::refused(what + ": the drone's estimated place (" + number(ctx.position.x()) + ", " +
                                number(ctx.position.y()) + ") m is " + number(outside_m) +
                                " m outside the geofence, beyond the walls: its pose is lost. Set the drone on its "
                                "platform and restart LaboDrone before it flies again");
}

}  // namespace

CommandResult check_request(const MissionRequest& r, const RequestContext& ctx, const fusion::LabGeometry& lab,
                            const Geofence& fence, const ControlConfig& config) {
  const std::string what = to_string(r.kind);
  if (r.kind == RequestKind::EmergencyStop) return CommandResult::ok("emergency stop: motors cut");
  if (!r.target.allFinite() || !std::isfinite(r.hold_s) || !std::isfinite(r.standoff_m))
    return CommandResult::refused(what + ": values must be finite numbers (got NaN or infinity)");
  if (ctx.phase == FlightPhase::Emergency && r.kind != RequestKind::Takeoff)
    return CommandResult::refused(what + ": the drone is in emergency; take off again to reset it");

  const bool mission_running = !ctx.running_mission.empty();
  const bool landed = !airborne(ctx.phase);
  switch (r.kind) {
    case RequestKind::Takeoff:
      if (!landed) return CommandResult::refused("takeoff: the drone is already " + to_string(ctx.phase));
      if (ctx.link != LinkState::Connected) return CommandResult::refused("takeoff: no link to the drone (" + to_string(ctx.link) + ")");
      if (ctx.battery_percent < config.safety.low_battery_percent)
        return CommandResult::refused("takeoff: battery " + number(ctx.battery_percent) + " % is below " +
                                      number(config.safety.low_battery_percent) + " %");
      if (auto lost = refuse_lost_pose(what, ctx, fence, config)) return *lost;
      return CommandResult::ok("taking off");
    case RequestKind::Land:
    case RequestKind::Hover:
    case RequestKind::ReturnHome:
      if (landed) return CommandResult::refused(what + ": needs flight, the drone is " + to_string(ctx.phase));
      return CommandResult::ok(what + (mission_running ? " (mission '" + ctx.running_mission + "' cancelled)" : ""));
    case RequestKind::Goto:
    case RequestKind::MoveBy: {
      if (landed) return CommandResult::refused(what + ": needs flight, the drone is " + to_string(ctx.phase));
      if (mission_running)
        return CommandResult::refused(what + ": mission '" + ctx.running_mission + "' is running (" + ctx.running_stage +
                                      "); stop it first (hover, land or return home)");
      const Eigen::Vector3d dest = destination(r, ctx);
      if (!fence.contains(dest)) return CommandResult::refused(what + ": " + fence.violation(dest));
      return CommandResult::ok(what + " to (" + number(dest.x()) + ", " + number(dest.y()) + ", " + number(dest.z()) + ") m");
    }
    case RequestKind::Inspect: {
      if (mission_running)
        return CommandResult::refused("inspect: mission '" + ctx.running_mission + "' is running (" + ctx.running_stage + ")");
      if (!lab.find_instrument(r.instrument_id))
        return CommandResult::refused("inspect: unknown instrument '" + r.instrument_id + "' (known: " + known_instruments(lab) + ")");
      const double standoff = r.standoff_m > 0 ? r.standoff_m : config.mission.standoff_m;
      if (r.standoff_m < 0 || standoff < config.mission.min_standoff_m)
        return CommandResult::refused("inspect: standoff " + number(r.standoff_m) + " m is below the safe minimum " +
                                      number(config.mission.min_standoff_m) + " m");
      if (r.hold_s < 0 || r.hold_s > config.mission.max_hold_s)
        return CommandResult::refused("inspect: hold time " + number(r.hold_s) + " s is outside [0, " +
                                      number(config.mission.max_hold_s) + "] s");
      const PoseTarget stand = standoff_target(lab.find_instrument(r.instrument_id)->T_world_object, standoff);
      if (!fence.contains(stand.position))
        return CommandResult::refused("inspect: the standoff point is outside the geofence: " + fence.violation(stand.position));
      if (landed && ctx.link != LinkState::Connected) return CommandResult::refused("inspect: no link to the drone");
      if (ctx.battery_percent < config.safety.low_battery_percent)
        return CommandResult::refused("inspect: battery " + number(ctx.battery_percent) + " % is below " +
                                      number(config.safety.low_battery_percent) + " %");
      if (auto lost = refuse_lost_pose(what, ctx, fence, config)) return *lost;
      return CommandResult::ok("inspecting '" + r.instrument_id + "' at " + number(standoff) + " m");
    }
    case RequestKind::FindTeacher:
      if (mission_running)
        return CommandResult::refused("find_teacher: mission '" + ctx.running_mission + "' is running (" + ctx.running_stage + ")");
      if (landed && ctx.link != LinkState::Connected) return CommandResult::refused("find_teacher: no link to the drone");
      if (ctx.battery_percent < config.safety.low_battery_percent)
        return CommandResult::refused("find_teacher: battery " + number(ctx.battery_percent) + " % is below " +
                                      number(config.safety.low_battery_percent) + " %");
      if (auto lost = refuse_lost_pose(what, ctx, fence, config)) return *lost;
      return CommandResult::ok("searching for the teacher");
    case RequestKind::SelectCamera:
      // A mission's stages need their camera (the panel and SLAM in front, the platform below).
      if (mission_running)
        return CommandResult::refused("select_camera: mission '" + ctx.running_mission + "' chooses the camera while it runs (" +
                                      ctx.running_stage + "); choose one when no mission runs");
      return CommandResult::ok(std::string("streaming the ") + (r.camera == CameraId::Bottom ? "bottom" : "front") + " camera");
    case RequestKind::StopFaceFollow:
      if (!ctx.mission_accepts_stop_face_follow) return CommandResult::refused("stop_face_follow: no face-follow is running");
      return CommandResult::ok("face-follow stopping");
    case RequestKind::EmergencyStop:
      break;
  }
  return CommandResult::refused(what + ": not understood");
}

}  // namespace labo::control
