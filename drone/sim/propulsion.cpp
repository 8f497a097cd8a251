#include "drone/sim/propulsion.hpp"

#include <algorithm>
#include <cmath>

namespace labo::sim {

Propulsion::Propulsion(const RotorParams& rotors, const BatteryParams& battery)
    : rotors_(rotors), battery_(battery), percent_(battery.start_percent) {
  voltage_ = battery_.empty_voltage_v + (battery_.full_voltage_v - battery_.empty_voltage_v) * percent_ / 100.0;
}

void Propulsion::step(const RotorThrusts& demand_n, bool running, Seconds dt) {
  double total = 0;
  for (double t : thrust_) total += t;
  const double open_circuit =
      battery_.empty_voltage_v + (battery_.full_voltage_v - battery_.empty_voltage_v) * percent_ / 100.0;
  voltage_ = std::max(0.0, open_circuit - battery_.internal_resistance_ohm * battery_.current_a_per_n * total);
  const double supply = std::pow(voltage_ / battery_.reference_voltage_v, 2);
  const double follow = 1.0 - std::exp(-dt / rotors_.lag_s);
  for (std::size_t i = 0; i < thrust_.size(); ++i) {
    const double target =
        running ? std::clamp(demand_n[i], rotors_.min_thrust_n, rotors_.max_thrust_n) * rotors_.efficiency[i] * supply : 0.0;
    thrust_[i] += follow * (target - thrust_[i]);
  }
}

void Propulsion::drain(bool airborne, Seconds dt) {
  const double rate = airborne ? battery_.flying_drain_percent_per_s : battery_.idle_drain_percent_per_s;
  percent_ = std::max(0.0, percent_ - rate * dt);
}

}  // namespace labo::sim
