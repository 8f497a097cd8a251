#pragma once
// The one place where the Tello's wire conventions meet LaboDrone's (docs/tello.md "Sign
// conventions"). Tello: rc a (> 0 right), b (> 0 forward), c (> 0 up), d (> 0 clockwise), integers
// in [-100, 100]; state pitch > 0 nose up, roll > 0 right wing down, yaw > 0 clockwise, in degrees;
// vgx forward, vgy right, vgz down in dm/s; ag* in 0.001 g on the same axes; tof, h in cm.
// LaboDrone (drone/drone_link.hpp): roll > 0 right, pitch > 0 nose down (forward), gaz > 0 up,
// yaw_rate > 0 counter-clockwise; body x forward, y left, z up; SI units.
#include "drone/drone_link.hpp"
#include "drone/emulated_vehicle.hpp"
#include "drone/tello/tello_rc.hpp"
#include "drone/tello/tello_state.hpp"

namespace labo::tello {

// Each MoveCommand value in [-1, 1] times `limit_percent` (1-100), rounded; values outside [-1, 1]
// are clipped, non-finite ones give centred sticks (a hover).
RcSticks rc_from_move(const MoveCommand& command, int limit_percent = kMaxStick);
// The inverse for the emulator: sticks / 100, clipped to [-1, 1].
MoveCommand move_from_rc(const RcSticks& sticks);

// A ToF reading beyond this is out of the sensor's range: the sample's altitude is then h (docs/tello.md).
inline constexpr double kTofMaxCm = 1000.0;

// A state string's values in SI units and LaboDrone's signs. The string has no flight state and no
// clock: `control_state` comes from the link's own account (TelloFlightPhase), `sequence` counts the
// accepted strings, and has_drone_time stays false (`time` is the motors' running time).
void sample_from_state(const TelloState& state, Seconds t, std::uint32_t sequence, int control_state,
                       NavdataSample& sample);

// What the emulator reports for a vehicle: attitude, velocities and specific force from its
// telemetry in the Tello's units and signs; `height_m` (above the take-off point), `motors_s` (motors-on
// time) and the temperatures are the emulator's own account.
struct EmulatedStateExtras {
  double height_m = 0;
  double motors_s = 0;
  double temperature_c = 60;
};
TelloState state_from_telemetry(const VehicleTelemetry& telemetry, const EmulatedStateExtras& extras);

}  // namespace labo::tello
