#pragma once
// Safety rules, evaluated every tick before the mission runs (the emergency stop is not here: it is
// executed the moment it is requested, whatever the state):
//  - link lost: the AR.Drone hovers on its own; after link_loss_land_s LaboDrone sends land;
//  - battery below low_battery_percent: return home and land; below critical: land where it is;
//  - localization lost (no visual source while the mission needs one) for localization_lost_hover_s:
//    hover; for localization_lost_land_s: land; both after a grace the mission's stage may grant (the
//    return home flies on navdata odometry for up to return_dead_reckoning_s); the hover is a level
//    hold (altitude and yaw controlled, level_hold.hpp), not the firmware's, which keeps any altitude
//    a push left it at;
//  - the estimate jumped (the fused position moved between two ticks by more than estimate_jump_m
//    beyond what its velocity explains: a re-sync, a wrong visual fix): level hold for
//    estimate_jump_hold_s, so the drone does not fly off on a pose that just changed under it;
//  - the estimate beyond the walls (more than pose_lost_outside_fence_m outside the geofence): the
//    pose is lost, and a set point clamped into the fence would be flown at full speed from a place
//    the drone is not at: land;
//  - too close to the surface below (ultrasound under min_clearance_m while flying, whatever the
//    estimate says): brake and climb until min_clearance_m + 0.15 m. This is the net under a bad
//    estimate: the drone cannot descend onto a bench or the floor, nor fly over a bench top at
//    instrument height.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "control/control_config.hpp"
#include "control/flight_types.hpp"

namespace labo::control {

// Ordered by precedence: the highest raised in a tick wins. Hover: the firmware's (link lost: the
// commands do not arrive anyway); HoldLevel: level_hold_command(); Climb: climb_command().
enum class SafetyAction { None, Hover, HoldLevel, ReturnHome, Climb, Land };
std::string to_string(SafetyAction action);

struct SafetyInputs {
  Seconds t = 0;
  bool airborne = false;  // flying, taking off or landing
  bool landing = false;
  LinkState link = LinkState::Connected;
  double battery_percent = 100;
  bool localization_required = false;
  bool localization_ok = true;
  double localization_grace_s = 0;  // dead reckoning tolerated this long before the escalation
  bool returning_home = false;
  bool flying = false;                  // airborne, neither taking off nor landing: clearance applies
  std::optional<double> ultrasound_m;   // navdata range to the surface below
  std::optional<Eigen::Vector3d> position_m;  // the fused estimate this tick
  double outside_fence_m = 0;  // how far the estimate lies outside the geofence over the floor
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
};

// What a safety rule (or the hold envelope) says this tick, as a kind and its figures: raised on
// every tick while it lasts, it is formatted into a sentence only where it is shown (to_string), so a
// tick allocates nothing however many rules are active.
enum class SafetyAlertKind {
  LinkLost,               // a: seconds lost, b: land after
  CriticalBattery,        // a: percent, b: the critical limit
  LowBattery,             // a: percent, b: the low limit
  PoseOutsideFence,       // a: metres outside
  LocalizationLostLand,   // a: seconds lost
  LocalizationLostHover,  // a: seconds lost, b: land at
  DeadReckoning,          // a: seconds on dead reckoning, b: tolerated for
  EstimateJumped,         // a: metres, b: hold until
  LowClearance,           // a: range below, b: the minimum
  LinkCutHover,           // the hold envelope: too fast for a link cut, hovering
  LinkCutScaled,          // ... the command scaled to a (fraction); the last kind
};
inline constexpr std::size_t kSafetyAlertKinds = static_cast<std::size_t>(SafetyAlertKind::LinkCutScaled) + 1;

struct SafetyAlert {
  SafetyAlertKind kind = SafetyAlertKind::LinkLost;
  double a = 0;
  double b = 0;
};
std::string to_string(const SafetyAlert& alert);

// The alerts of one tick: at most one per kind.
class SafetyAlerts {
 public:
  static constexpr std::size_t kCapacity = kSafetyAlertKinds;
  void push_back(const SafetyAlert& alert) {
    if (size_ < kCapacity) alerts_[size_++] = alert;
  }
  void clear() { size_ = 0; }
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  const SafetyAlert& operator[](std::size_t i) const { return alerts_[i]; }
  const SafetyAlert& back() const { return alerts_[size_ - 1]; }
  const SafetyAlert* begin() const { return alerts_.data(); }
  const SafetyAlert* end() const { return alerts_.data() + size_; }

 private:
  std::array<SafetyAlert, kCapacity> alerts_{};
  std::size_t size_ = 0;
};

struct SafetyVerdict {
  SafetyAction action = SafetyAction::None;
  SafetyAlert reason;  // the rule behind action (when not None)
  SafetyAlerts alerts;
};

class SafetyMonitor {
 public:
  explicit SafetyMonitor(const SafetyLimits& limits) : limits_(limits) {}
  SafetyVerdict evaluate(const SafetyInputs& in);
  int estimate_jumps() const { return jumps_; }  // counted since start

 private:
  // Sets jump_hold_until_ when the estimate moved more than its velocity explains since last tick.
  void watch_estimate(const SafetyInputs& in);

  SafetyLimits limits_;
  Seconds link_lost_since_ = -1;
  Seconds localization_lost_since_ = -1;
  bool low_clearance_ = false;
  std::optional<Eigen::Vector3d> last_position_;
  Seconds last_t_ = 0;
  Seconds jump_hold_until_ = -1;
  double last_jump_m_ = 0;
  int jumps_ = 0;
};

}  // namespace labo::control
