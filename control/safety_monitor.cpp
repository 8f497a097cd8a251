#include "control/safety_monitor.hpp"

#include <algorithm>
#include <cstdio>

namespace labo::control {

std::string to_string(SafetyAction action) {
  switch (action) {
    case SafetyAction::None: return "none";
    case SafetyAction::Hover: return "hover";
    case SafetyAction::HoldLevel: return "hold_level";
    case SafetyAction::ReturnHome: return "return_home";
    case SafetyAction::Climb: return "climb";
    case SafetyAction::Land: return "land";
  }
  return "unknown";
}

namespace {
constexpr double kClearanceHysteresisM = 0.15;
constexpr Seconds kMaxJumpCheckDt = 0.5;  // a longer gap between ticks: no comparison

std::string printf_string(const char* fmt, double a, double b = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
}  // namespace

std::string to_string(const SafetyAlert& alert) {
  const double a = alert.a, b = alert.b;
  switch (alert.kind) {
    case SafetyAlertKind::LinkLost: return printf_string("link lost for %.1f s (land after %.1f s)", a, b);
    case SafetyAlertKind::CriticalBattery: return printf_string("battery %.0f %% below the critical %.0f %%: landing here", a, b);
    case SafetyAlertKind::LowBattery: return printf_string("battery %.0f %% below %.0f %%: returning home", a, b);
    case SafetyAlertKind::PoseOutsideFence:
      return printf_string("the position estimate is %.2f m outside the geofence: the pose is lost, landing", a);
    case SafetyAlertKind::LocalizationLostLand: return printf_string("localization lost for %.1f s: landing", a);
    case SafetyAlertKind::LocalizationLostHover:
      return printf_string("localization lost for %.1f s: hovering (land at %.1f s)", a, b);
    case SafetyAlertKind::DeadReckoning: return printf_string("dead reckoning for %.1f s (tolerated for %.1f s)", a, b);
    case SafetyAlertKind::EstimateJumped: return printf_string("the estimate jumped %.2f m: holding level until %.1f s", a, b);
    case SafetyAlertKind::LowClearance: return printf_string("%.2f m above the surface below (minimum %.2f m): climbing", a, b);
    case SafetyAlertKind::LinkCutHover: return "too fast for a link cut here: hovering";
    case SafetyAlertKind::LinkCutScaled: return printf_string("too fast for a link cut here: command at %.0f %%", 100.0 * a);
  }
  return "unknown safety alert";
}

SafetyVerdict SafetyMonitor::evaluate(const SafetyInputs& in) {
  SafetyVerdict v;
  auto raise = [&](SafetyAction a, const SafetyAlert& reason) {
    if (static_cast<int>(a) > static_cast<int>(v.action)) {
      v.action = a;
      v.reason = reason;
    }
    v.alerts.push_back(reason);
  };

  const bool link_down = in.link == LinkState::Lost || in.link == LinkState::Disconnected;
  if (!link_down) link_lost_since_ = -1;
  else if (link_lost_since_ < 0) link_lost_since_ = in.t;
  if (link_down && in.airborne) {
    const double lost = in.t - link_lost_since_;
    raise(lost >= limits_.link_loss_land_s ? SafetyAction::Land : SafetyAction::Hover,
          {SafetyAlertKind::LinkLost, lost, limits_.link_loss_land_s});
  }

  if (in.airborne && in.battery_percent < limits_.critical_battery_percent) {
    raise(SafetyAction::Land, {SafetyAlertKind::CriticalBattery, in.battery_percent, limits_.critical_battery_percent});
  } else if (in.airborne && !in.landing && in.battery_percent < limits_.low_battery_percent && !in.returning_home) {
    raise(SafetyAction::ReturnHome, {SafetyAlertKind::LowBattery, in.battery_percent, limits_.low_battery_percent});
  }

  if (in.airborne && !in.landing && limits_.pose_lost_outside_fence_m > 0 &&
      in.outside_fence_m > limits_.pose_lost_outside_fence_m)
    raise(SafetyAction::Land, {SafetyAlertKind::PoseOutsideFence, in.outside_fence_m});

  const bool lost = in.airborne && in.localization_required && !in.localization_ok;
  if (!lost) localization_lost_since_ = -1;
  else if (localization_lost_since_ < 0) localization_lost_since_ = in.t;
  if (lost) {
    const double d = in.t - localization_lost_since_;
    const double grace = std::max(0.0, in.localization_grace_s);
    if (d >= grace + limits_.localization_lost_land_s)
      raise(SafetyAction::Land, {SafetyAlertKind::LocalizationLostLand, d});
    else if (d >= grace + limits_.localization_lost_hover_s)
      raise(SafetyAction::HoldLevel, {SafetyAlertKind::LocalizationLostHover, d, grace + limits_.localization_lost_land_s});
    else if (grace > 0)
      v.alerts.push_back({SafetyAlertKind::DeadReckoning, d, grace});
  }

  watch_estimate(in);
  if (in.flying && in.t < jump_hold_until_)
    raise(SafetyAction::HoldLevel, {SafetyAlertKind::EstimateJumped, last_jump_m_, jump_hold_until_});

  if (!in.flying || !in.ultrasound_m || limits_.min_clearance_m <= 0) {
    low_clearance_ = false;
  } else if (*in.ultrasound_m < limits_.min_clearance_m) {
    low_clearance_ = true;
  } else if (*in.ultrasound_m > limits_.min_clearance_m + kClearanceHysteresisM) {
    low_clearance_ = false;
  }
  if (low_clearance_)
    raise(SafetyAction::Climb, {SafetyAlertKind::LowClearance, *in.ultrasound_m, limits_.min_clearance_m});
  return v;
}

void SafetyMonitor::watch_estimate(const SafetyInputs& in) {
  if (!in.position_m || !in.position_m->allFinite()) {
    last_position_.reset();
    return;
  }
  const double dt = in.t - last_t_;
  if (last_position_ && dt > 0 && dt <= kMaxJumpCheckDt && limits_.estimate_jump_m > 0) {
    const double unexplained = (*in.position_m - *last_position_ - in.velocity_mps * dt).norm();
    if (unexplained > limits_.estimate_jump_m) {
      ++jumps_;
      last_jump_m_ = unexplained;
      jump_hold_until_ = in.t + limits_.estimate_jump_hold_s;
    }
  }
  last_position_ = in.position_m;
  last_t_ = in.t;
}

}  // namespace labo::control
