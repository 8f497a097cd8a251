#pragma once
// A run's world (drone/sim/sim_world.hpp) as JSON for the campaign outputs: the mode and seed, and
// what the world is made of: the drone's deviations and battery, the sensors' biases, every object's
// placement offset, the cameras' intrinsics and mounting tilt, the delays, the events that fell in
// the run and the teacher's walk.
#include <nlohmann/json.hpp>

#include "core/time.hpp"
#include "drone/sim/sim_world.hpp"

namespace labo::bench {

using sim::SimWorld;


// `until_s`: events starting after it (the run's end) are left out.
nlohmann::json world_json(const SimWorld& world, Seconds until_s);

}  // namespace labo::bench
