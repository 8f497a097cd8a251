#pragma once
// The "sim" configuration section: everything the simulated lab and its lockstep link need that is
// not the lab's geometry (lab.json) or the real-time emulator's ports ("emulator"). Every key is
// optional (defaults in docs/sim.md), range-checked, and unknown keys are refused.
#include <vector>

#include "drone/sim/sim_drone_link.hpp"
#include "drone/sim/simulated_lab.hpp"
#include "drone/sim/world_mode.hpp"

namespace labo {
class ConfigReader;
}  // namespace labo

namespace labo::sim {

struct SimConfig {
  SimulatedLabSettings lab;  // seed, physics step, dynamics, sensors, teacher, disturbances
  SimLinkSettings link;      // lockstep link: delays, jitter, loss, H.264
  WorldMode world = WorldMode::Nominal;  // "world": nominal, or randomized around the above per seed
};

// Throws ConfigError "<file>: sim.<key>: <value> ... expected <range>".
SimConfig read_sim_config(const ConfigReader& section);
// The "sim" section of a whole configuration, with the sim link's video bit rate taken from the
// driver's "link" section (link.video_max_bitrate_kbps, validated with the rest of that section).
SimConfig read_sim_config_of(const ConfigReader& root);

}  // namespace labo::sim
