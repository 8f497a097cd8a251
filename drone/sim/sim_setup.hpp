#pragma once
// The one place that decides how the simulated lab is assembled: which SceneRenderer draws its
// cameras, and a SimulatedLab built from a lab description. Switching renderers happens here only.
#include <filesystem>
#include <memory>
#include <optional>

#include "core/camera_config.hpp"
#include "drone/ardrone2/ardrone_emulator.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo {

// The renderer of the simulated lab's cameras, at the sizes and intrinsics of `cameras`.
// Currently the fallback FlatSceneRenderer (drone/sim/flat_scene_renderer.hpp).
std::unique_ptr<SceneRenderer> make_scene_renderer(const LabDescription& lab, const CamerasConfig& cameras);

// A simulated lab with make_scene_renderer()'s cameras.
std::unique_ptr<SimulatedLab> make_simulated_lab(const LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings);

// What the simulated lab's own commands (emulate, bench sim) read from a configuration file: only
// their sections (cameras, emulator, sim, lab); `labodrone serve` validates the whole file.
struct SimInputs {
  LabDescription lab;
  CamerasConfig cameras;
  SimConfig sim;
  ArdroneEmulatorSettings emulator;
};
// `lab_file` overrides the config's "lab". Throws ConfigError naming the file, key and reason.
SimInputs load_sim_inputs(const std::filesystem::path& config_file,
                          const std::optional<std::filesystem::path>& lab_file = std::nullopt);

}  // namespace labo
