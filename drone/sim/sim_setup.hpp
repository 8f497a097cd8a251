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
#include "drone/sim/head_model.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/sim_world.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo::sim {

// The renderer of the simulated lab's cameras, at the sizes and intrinsics of `cameras`: LabRenderer
// (drone/sim/lab_renderer.hpp, docs/sim_rendering.md), the teacher's face textured from `head`
// (localization/face/teacher_head.hpp builds it; without it the head is drawn untextured), the sensor
// noise drawn from `seed`.
std::unique_ptr<SceneRenderer> make_scene_renderer(const lab::LabDescription& lab, const CamerasConfig& cameras,
                                                   std::optional<TexturedHeadModel> head, unsigned seed,
                                                   const CameraMounts& mounts = {});

// A simulated lab with make_scene_renderer()'s cameras (noise seeded by settings.seed).
std::unique_ptr<SimulatedLab> make_simulated_lab(const lab::LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings,
                                                 std::optional<TexturedHeadModel> head = std::nullopt);
// The simulated lab of a world (drone/sim/sim_world.hpp): its lab, cameras and mountings, its drone.
// Its link settings (world.link) are for the SimDroneLink that flies it in lockstep.
std::unique_ptr<SimulatedLab> make_simulated_lab(const SimWorld& world, std::optional<TexturedHeadModel> head = std::nullopt);

// What the simulated lab's own commands (emulate, bench sim) read from a configuration file: only
// their sections (cameras, emulator, sim, lab); `labodrone serve` validates the whole file.
struct SimInputs {
  lab::LabDescription lab;
  CamerasConfig cameras;
  SimConfig sim;
  ardrone2::ArdroneEmulatorSettings emulator;
};
// `lab_file` overrides the config's "lab". Throws ConfigError naming the file, key and reason.
SimInputs load_sim_inputs(const std::filesystem::path& config_file,
                          const std::optional<std::filesystem::path>& lab_file = std::nullopt);

}  // namespace labo::sim
