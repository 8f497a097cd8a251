#include "control/control_config.hpp"

#include <numbers>

namespace labo::control {

namespace {

PidGains read_pid(const ConfigReader& node, PidGains g) {
  g.kp = node.number_or("kp", g.kp, Range::non_negative());
  g.ki = node.number_or("ki", g.ki, Range::non_negative());
  g.kd = node.number_or("kd", g.kd, Range::non_negative());
  g.integral_limit = node.number_or("integral_limit", g.integral_limit, Range::non_negative());
  g.integral_zone = node.number_or("integral_zone", g.integral_zone, Range::non_negative());
  g.out_min = node.number_or("out_min", g.out_min, Range::closed(-1.0, 0.0));
  g.out_max = node.number_or("out_max", g.out_max, Range::closed(0.0, 1.0));
  node.finish();
  return g;
}

PoseControlGains read_gains(const ConfigReader& node, PoseControlGains g) {
  if (node.has("xy")) g.xy = read_pid(node.object("xy"), g.xy);
  if (node.has("z")) g.z = read_pid(node.object("z"), g.z);
  if (node.has("yaw")) g.yaw = read_pid(node.object("yaw"), g.yaw);
  g.max_tilt_command = node.number_or("max_tilt_command", g.max_tilt_command, {0.0, 1.0, true});
  g.xy_velocity_feedforward = node.number_or("xy_velocity_feedforward", g.xy_velocity_feedforward, Range::closed(0.0, 2.0));
  g.yaw_rate_feedforward = node.number_or("yaw_rate_feedforward", g.yaw_rate_feedforward, Range::closed(0.0, 2.0));
  node.finish();
  return g;
}

AutopilotCriteria read_autopilot(const ConfigReader& node, AutopilotCriteria a) {
  a.reach_distance_m = node.number_or("reach_distance_m", a.reach_distance_m, Range::positive());
  a.reach_yaw_rad = node.number_or("reach_yaw_deg", a.reach_yaw_rad * 180.0 / std::numbers::pi, {0.0, 180.0, true}) * std::numbers::pi / 180.0;
  a.stay_distance_m = node.number_or("stay_distance_m", a.stay_distance_m, Range::positive());
  a.stay_time_s = node.number_or("stay_time_s", a.stay_time_s, Range::non_negative());
  a.takeoff_time_s = node.number_or("takeoff_time_s", a.takeoff_time_s, Range::closed(0.5, 30.0));
  a.land_time_s = node.number_or("land_time_s", a.land_time_s, Range::closed(0.5, 30.0));
  node.finish();
  if (a.stay_distance_m < a.reach_distance_m) node.fail("stay_distance_m", "must be >= reach_distance_m");
  return a;
}

MissionParameters read_mission(const ConfigReader& node, MissionParameters m) {
  m.standoff_m = node.number_or("standoff_m", m.standoff_m, Range::closed(0.2, 5.0));
  m.min_standoff_m = node.number_or("min_standoff_m", m.min_standoff_m, Range::closed(0.2, 5.0));
  m.face_distance_m = node.number_or("face_distance_m", m.face_distance_m, Range::closed(0.3, 5.0));
  m.cruise_altitude_m = node.number_or("cruise_altitude_m", m.cruise_altitude_m, Range::closed(0.3, 5.0));
  m.return_altitude_m = node.number_or("return_altitude_m", m.return_altitude_m, Range::closed(0.3, 5.0));
  m.platform_hover_altitude_m =
      node.number_or("platform_hover_altitude_m", m.platform_hover_altitude_m, Range::closed(0.3, 5.0));
  m.landing_centre_tolerance_m =
      node.number_or("landing_centre_tolerance_m", m.landing_centre_tolerance_m, Range::closed(0.005, 0.5));
  m.landing_settle_s = node.number_or("landing_settle_s", m.landing_settle_s, Range::closed(0.0, 10.0));
  m.platform_settle_timeout_s =
      node.number_or("platform_settle_timeout_s", m.platform_settle_timeout_s, Range::closed(1.0, 120.0));
  m.scale_manoeuvre_m = node.number_or("scale_manoeuvre_m", m.scale_manoeuvre_m, Range::closed(0.0, 2.0));
  m.scale_manoeuvre_speed_mps =
      node.number_or("scale_manoeuvre_speed_mps", m.scale_manoeuvre_speed_mps, Range::closed(0.05, 1.0));
  m.detect_timeout_s = node.number_or("detect_timeout_s", m.detect_timeout_s, Range::positive());
  m.detect_max_oblique_deg = node.number_or("detect_max_oblique_deg", m.detect_max_oblique_deg, Range::closed(0.0, 90.0));
  m.detect_view_distance_m = node.number_or("detect_view_distance_m", m.detect_view_distance_m, Range::closed(0.5, 10.0));
  m.hold_tolerance_m = node.number_or("hold_tolerance_m", m.hold_tolerance_m, Range::closed(0.01, 0.5));
  m.default_hold_s = node.number_or("default_hold_s", m.default_hold_s, Range::non_negative());
  m.max_hold_s = node.number_or("max_hold_s", m.max_hold_s, Range::positive());
  m.face_search_yaw_rate = node.number_or("face_search_yaw_rate", m.face_search_yaw_rate, Range::closed(0.05, 2.0));
  m.face_blind_altitude_m = node.number_or("face_blind_altitude_m", m.face_blind_altitude_m, Range::closed(0.3, 5.0));
  m.face_as_feedback = node.boolean_or("face_as_feedback", m.face_as_feedback);
  m.face_search_timeout_s = node.number_or("face_search_timeout_s", m.face_search_timeout_s, Range::positive());
  m.source_switch.far_to_near_m = node.number_or("far_to_near_m", m.source_switch.far_to_near_m, Range::positive());
  m.source_switch.near_to_far_m = node.number_or("near_to_far_m", m.source_switch.near_to_far_m, Range::positive());
  m.source_switch.source_hold_s = node.number_or("source_hold_s", m.source_switch.source_hold_s, Range::non_negative());
  node.finish();
  if (m.standoff_m < m.min_standoff_m) node.fail("standoff_m", "must be >= min_standoff_m");
  if (m.source_switch.near_to_far_m <= m.source_switch.far_to_near_m) node.fail("near_to_far_m", "must be > far_to_near_m (hysteresis)");
  if (m.default_hold_s > m.max_hold_s) node.fail("default_hold_s", "must be <= max_hold_s");
  return m;
}

SafetyLimits read_safety(const ConfigReader& node, SafetyLimits s) {
  s.link_loss_land_s = node.number_or("link_loss_land_s", s.link_loss_land_s, Range::closed(0.5, 60.0));
  s.low_battery_percent = node.number_or("low_battery_percent", s.low_battery_percent, Range::closed(0.0, 100.0));
  s.critical_battery_percent =
      node.number_or("critical_battery_percent", s.critical_battery_percent, Range::closed(0.0, 100.0));
  s.localization_lost_hover_s =
      node.number_or("localization_lost_hover_s", s.localization_lost_hover_s, Range::closed(0.0, 60.0));
  s.localization_lost_land_s =
      node.number_or("localization_lost_land_s", s.localization_lost_land_s, Range::closed(0.0, 300.0));
  s.return_dead_reckoning_s =
      node.number_or("return_dead_reckoning_s", s.return_dead_reckoning_s, Range::closed(0.0, 120.0));
  s.geofence_margin_m = node.number_or("geofence_margin_m", s.geofence_margin_m, Range::closed(0.0, 2.0));
  s.min_clearance_m = node.number_or("min_clearance_m", s.min_clearance_m, Range::closed(0.0, 1.5));
  s.estimate_jump_m = node.number_or("estimate_jump_m", s.estimate_jump_m, Range::closed(0.0, 5.0));
  s.pose_lost_outside_fence_m =
      node.number_or("pose_lost_outside_fence_m", s.pose_lost_outside_fence_m, Range::closed(0.0, 10.0));
  s.estimate_jump_hold_s = node.number_or("estimate_jump_hold_s", s.estimate_jump_hold_s, Range::closed(0.0, 10.0));
  s.hold_clearance_m = node.number_or("hold_clearance_m", s.hold_clearance_m, Range::closed(-1.0, 1.0));
  node.finish();
  if (s.critical_battery_percent > s.low_battery_percent)
    node.fail("critical_battery_percent", "must be <= low_battery_percent");
  if (s.localization_lost_land_s < s.localization_lost_hover_s)
    node.fail("localization_lost_land_s", "must be >= localization_lost_hover_s");
  return s;
}

}  // namespace

ControlConfig read_control_config(const ConfigReader& node) {
  ControlConfig c;
  if (node.has("gains")) c.gains = read_gains(node.object("gains"), c.gains);
  if (node.has("autopilot")) c.autopilot = read_autopilot(node.object("autopilot"), c.autopilot);
  if (node.has("mission")) c.mission = read_mission(node.object("mission"), c.mission);
  if (node.has("safety")) c.safety = read_safety(node.object("safety"), c.safety);
  c.control_rate_hz = node.number_or("control_rate_hz", c.control_rate_hz, Range::closed(5.0, 200.0));
  node.finish();
  return c;
}

}  // namespace labo::control
