#pragma once
// The one place that decides how the simulated lab is assembled: which SceneRenderer draws its
// cameras, and a SimulatedLab built from a lab description. Switching renderers happens here only.
#include <memory>

#include "core/camera_config.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/scene_renderer.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo {

// The renderer of the simulated lab's cameras, at the sizes and intrinsics of `cameras`.
// Currently the fallback FlatSceneRenderer (drone/sim/flat_scene_renderer.hpp).
std::unique_ptr<SceneRenderer> make_scene_renderer(const LabDescription& lab, const CamerasConfig& cameras);

// A simulated lab with make_scene_renderer()'s cameras.
std::unique_ptr<SimulatedLab> make_simulated_lab(const LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings);

}  // namespace labo
