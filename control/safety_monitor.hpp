#pragma once
// Safety rules, evaluated every tick before the mission runs (the emergency stop is not here: it is
// executed the moment it is requested, whatever the state):
//  - link lost: the AR.Drone hovers on its own; after link_loss_land_s LaboDrone sends land;
//  - battery below low_battery_percent: return home and land; below critical: land where it is;
//  - localization lost (no visual source while the mission needs one) for localization_lost_hover_s:
//    hover; for localization_lost_land_s: land; both after a grace the mission's stage may grant (the
//    return home flies on navdata odometry for up to return_dead_reckoning_s).
#include <string>
#include <vector>

#include "control/control_config.hpp"
#include "control/flight_types.hpp"

namespace labo {

enum class SafetyAction { None, Hover, ReturnHome, Land };
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
};

struct SafetyVerdict {
  SafetyAction action = SafetyAction::None;
  std::string reason;
  std::vector<std::string> alerts;
};

class SafetyMonitor {
 public:
  explicit SafetyMonitor(const SafetyLimits& limits) : limits_(limits) {}
  SafetyVerdict evaluate(const SafetyInputs& in);

 private:
  SafetyLimits limits_;
  Seconds link_lost_since_ = -1;
  Seconds localization_lost_since_ = -1;
};

}  // namespace labo
