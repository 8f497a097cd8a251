#pragma once
// Configuration of flight control, read from the "control" section of config/default.json: PID gains
// and limits per axis, the autopilot's reach/stay criteria, mission parameters and safety limits.
// Defaults follow tum_ardrone's controller (notes/tum_ardrone.md §4-5) and were then tuned on the
// simulated lab (docs/control.md says how).
#include "core/config_reader.hpp"
#include "localization/fusion/localization_switch.hpp"

namespace labo::control {

// One PID axis. Output = clip(kp*e + ki*I + kd*de, out_min, out_max); the integral I is capped at
// |I| <= integral_limit (in units of error*s) and decays faster when the error opposes it.
struct PidGains {
  double kp = 0;
  double ki = 0;
  double kd = 0;
  double integral_limit = 0;  // error*s; 0 disables the integral term
  double out_min = -1;
  double out_max = 1;
  // |error| beyond which the integral holds still (it still unwinds when the error opposes it); 0:
  // everywhere. A bias is removed near the set point; a manoeuvre's or a moving set point's error is
  // the derivative's and the proportional's business.
  double integral_zone = 0;
};

struct PoseControlGains {
  // Tuned in lockstep (docs/control.md): tum_ardrone's xy 0.5/0.35 -> 0.7/0.4, which recovers from a
  // perturbation sooner and keeps a followed face nearer the image's centre; yaw 2.0 per rad.
  // xy integral: an attitude the firmware holds a little off level (its trim, a sensor's bias) is a
  // constant push, and proportional control alone settles 3-5 cm off the set point against it (the
  // randomized world's hover above the platform). 0.15 per m s, capped at 0.5 m s (at most 0.075 of
  // the command): a few seconds to remove it, too slow to fight the derivative in a manoeuvre.
  // It integrates only within 0.15 m of a still set point (tests "control: a vertical push out of the
  // panel's view ..." and the face-follow route's RMS failed with it everywhere).
  PidGains xy{0.7, 0.15, 0.4, 0.5, -1.0, 1.0, 0.15};    // -> roll / pitch
  // z: tum_ardrone's 0.6/0.001/0.1 clipped to [-0.25, 0.8] -> 1.5/0.001/0.5 in [-0.5, 0.8]
  // (docs/control.md; test "control: the default z gains recover a 0.6 m/s vertical push on the
  // firmware's dynamics within 4 s").
  PidGains z{1.5, 0.001, 0.5, 200.0, -0.5, 0.8};         // -> gaz
  PidGains yaw{2.0, 0.0, 0.0, 0.0, -1.0, 1.0};           // -> yaw rate (rad error -> command)
  double max_tilt_command = 0.5;  // |roll|, |pitch| clip below the PCMD range, for a gentle flight
  // Tilt command per m/s of a moving set point: holds the speed against drag without a lagging error
  // (drag 0.5-0.55 /s over g * tan(12 deg) gives about 0.25).
  double xy_velocity_feedforward = 0.25;
  // Yaw-rate command per rad/s of a turning set point (a camera kept on a face while the drone goes
  // round it): the firmware's full-scale yaw rate is 100 deg/s (1.75 rad/s). Without it the yaw loop
  // (kp 2.0) lags a 0.5 rad/s turn by 0.15-0.25 rad.
  double yaw_rate_feedforward = 0.57;
};

struct AutopilotCriteria {
  double reach_distance_m = 0.20;   // a waypoint is reached inside this distance ...
  double reach_yaw_rad = 0.087;     // ... and this yaw error (5 deg)
  double stay_distance_m = 0.5;     // it completes after staying within this distance ...
  double stay_time_s = 2.0;         // ... for this long
  double takeoff_time_s = 5.0;      // firmware take-off sequence before control starts
  double land_time_s = 5.0;         // land sent; the drone is declared landed at control state 2
};

struct MissionParameters {
  double standoff_m = 0.80;            // inspect: hold distance to the panel
  double min_standoff_m = 0.40;        // refused below this
  double face_distance_m = 1.00;       // face-follow: hold distance to the face
  double cruise_altitude_m = 1.0;      // stage 1/2 altitude
  double return_altitude_m = 1.6;      // stage 4: higher, for a broad view of the floor
  double platform_hover_altitude_m = 0.9;  // stage 5
  // Stage 5 -> 6: the land command is sent once the drone has stayed this close above the platform's
  // centre (as the bottom camera places it), nearly still, for landing_settle_s; after
  // platform_settle_timeout_s it is sent wherever the drone is, and the result says so. The firmware's
  // own descent drifts by its velocity bias: what is off at the land command stays off.
  double landing_centre_tolerance_m = 0.03;
  double landing_settle_s = 0.5;
  double platform_settle_timeout_s = 12.0;
  double scale_manoeuvre_m = 0.5;      // stage 1: up/down amplitude for the scale estimation
  double scale_manoeuvre_speed_mps = 0.25;
  double detect_timeout_s = 15.0;      // stage 2 / re-detection: give up and go home after this
  // Stage 2: a panel seen more obliquely than this from where the drone is (its normal against the
  // line to the drone, horizontally) is searched for from a viewpoint on its normal, at
  // detect_view_distance_m or nearer when the drone already is: template matching does not find a
  // small panel foreshortened at 50 degrees from 4 m (the lab's power supply, seen from the base).
  double detect_max_oblique_deg = 30.0;
  double detect_view_distance_m = 2.5;
  double hold_tolerance_m = 0.04;      // inspect: hold time counts only this close to the standoff pose
  double default_hold_s = 10.0;        // inspect hold time when the request gives none
  double max_hold_s = 600.0;
  double face_search_yaw_rate = 0.4;   // rad/s during the yaw sweep
  // Face-follow: where the face is not seen and the drone moves (to a search viewpoint, round the
  // place the face was lost) or sweeps where it lost the face, it flies at this altitude, above a
  // standing adult's head: a teacher it cannot see may be walking where it flies. The highest it
  // watches a head followed without its face from.
  double face_blind_altitude_m = 2.0;
  // The teacher moves: fed to the filter as a landmark, the face's motion is taken for the drone's.
  // Off: SLAM drives the pose and the face is the target; the face drives it only when SLAM is lost.
  bool face_as_feedback = false;
  double face_search_timeout_s = 120.0;  // a watch at the teacher's route lasts one round of it (~35 s)
  fusion::SourceSwitchParameters source_switch;  // the localization switch's hysteresis
};

struct SafetyLimits {
  double link_loss_land_s = 5.0;       // land after the link has been lost this long
  double low_battery_percent = 20.0;   // return home and land below this
  double critical_battery_percent = 10.0;  // land where it is below this
  double localization_lost_hover_s = 1.0;  // hover when localization has been lost this long
  double localization_lost_land_s = 8.0;   // land after this long
  // On the way home (stages 4-5) the drone flies on navdata odometry while SLAM relocalizes (or is
  // off: the bottom camera streams) until the platform appears: tolerated this long before the
  // hover/land escalation above starts.
  double return_dead_reckoning_s = 20.0;
  double geofence_margin_m = 0.30;     // distance kept from walls, floor and ceiling
  // Ultrasound range below which a flying drone (not taking off or landing) brakes and climbs; 0: off.
  double min_clearance_m = 0.35;
  // A fused position moving this much more than its velocity explains between two ticks is a jump:
  // level hold for estimate_jump_hold_s; 0: off.
  double estimate_jump_m = 0.30;
  double estimate_jump_hold_s = 1.0;
  // A position estimate this far outside the geofence over the floor is beyond the walls: the pose is
  // lost, not the drone. In flight: land; on the ground: no mission takes off on it. 0: off.
  double pose_lost_outside_fence_m = 0.5;
  // Every move command is one the drone survives a link cut with: held for the firmware's command
  // hold and then braked, it must leave the drone this far inside the walls and the ceiling
  // (control/command_hold_envelope.hpp). Negative: off, the default: its bound is cautious enough to
  // cost the randomized world's campaigns more than the crashes it prevents (docs/control.md).
  double hold_clearance_m = -1.0;
};

struct ControlConfig {
  PoseControlGains gains;
  AutopilotCriteria autopilot;
  MissionParameters mission;
  SafetyLimits safety;
  double control_rate_hz = 30.0;
};

// Reads {"gains": {"xy"|"z"|"yaw": {kp, ki, kd, integral_limit, out_min, out_max}, max_tilt_command},
// "autopilot": {...}, "mission": {...}, "safety": {...}, "control_rate_hz"}; every key optional with
// the defaults above; refuses unknown keys and values out of range.
ControlConfig read_control_config(const ConfigReader& node);

}  // namespace labo::control
