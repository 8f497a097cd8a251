#pragma once
// Propulsion: the AR.Drone 2.0's four motors and its battery, between the firmware's thrust demands
// (FirmwareLoops) and the airframe (Airframe). The firmware maps a demanded thrust to a motor command
// as if the battery were at `reference_voltage_v`; what a rotor really gives is that demand, clipped
// to the motors' range, times its own efficiency and (V / V_ref)^2, where V is the battery's voltage
// under load: the open-circuit voltage of its charge minus the sag of the current through its internal
// resistance. Each rotor reaches its thrust through a first-order lag (motor and propeller spin-up).
// A sagging battery therefore asks the firmware's integrators for more, and leaves less headroom.
#include <array>

#include "core/time.hpp"
#include "drone/sim/airframe.hpp"

namespace labo::sim {

struct RotorParams {
  double max_thrust_n = 2.0;    // per rotor, at the reference voltage (thrust to weight about 1.9)
  double min_thrust_n = 0.05;   // idle in flight
  double lag_s = 0.03;          // motor and propeller spin-up
  std::array<double, 4> efficiency{1.0, 1.0, 1.0, 1.0};  // each rotor's thrust per demand
};

struct BatteryParams {
  double start_percent = 95.0;
  double flying_drain_percent_per_s = 0.125;  // about 13 minutes of flight
  double idle_drain_percent_per_s = 0.005;
  double low_percent = 20.0;                  // state bit 15; at 0 the firmware lands
  double full_voltage_v = 12.5;               // open circuit at 100 %, linear in the charge
  double empty_voltage_v = 11.0;              // ... at 0 %
  double internal_resistance_ohm = 0.08;
  double current_a_per_n = 1.2;               // current per newton of total thrust (about 5 A in hover)
  double reference_voltage_v = 12.0;          // the firmware's motor map assumes this voltage
};

class Propulsion {
 public:
  Propulsion(const RotorParams& rotors, const BatteryParams& battery);

  // One sub-step of `dt`: the rotors approach the demanded thrusts (clipped to the motors' range) as
  // the battery under this load delivers them. `running` false: motors off, thrusts fall to zero.
  void step(const RotorThrusts& demand_n, bool running, Seconds dt);
  // The charge drains by `dt` of flight (airborne) or idle time; 0 stays 0.
  void drain(bool airborne, Seconds dt);
  void stop() { thrust_.fill(0.0); }

  const RotorThrusts& thrust() const { return thrust_; }
  double charge_percent() const { return percent_; }
  double voltage_v() const { return voltage_; }
  const RotorParams& rotors() const { return rotors_; }
  const BatteryParams& battery() const { return battery_; }

 private:
  RotorParams rotors_;
  BatteryParams battery_;
  RotorThrusts thrust_{};
  double percent_;
  double voltage_;
};

}  // namespace labo::sim
