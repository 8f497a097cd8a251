#pragma once
// Which world the simulated lab flies (drone/sim/sim_world.hpp): `nominal`, the lab file, the
// configured calibration and the sim section exactly; `randomized`, a world drawn around them per seed.
#include <optional>
#include <string>
#include <string_view>

namespace labo::sim {

enum class WorldMode { Nominal, Randomized };

inline std::string to_string(WorldMode mode) { return mode == WorldMode::Nominal ? "nominal" : "randomized"; }

// "nominal" or "randomized"; anything else is nullopt.
inline std::optional<WorldMode> parse_world_mode(std::string_view text) {
  if (text == "nominal") return WorldMode::Nominal;
  if (text == "randomized") return WorldMode::Randomized;
  return std::nullopt;
}

}  // namespace labo::sim
