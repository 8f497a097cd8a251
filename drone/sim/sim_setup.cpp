#include "drone/sim/sim_setup.hpp"

#include "drone/sim/flat_scene_renderer.hpp"

namespace labo {

std::unique_ptr<SceneRenderer> make_scene_renderer(const LabDescription& lab, const CamerasConfig& cameras) {
  return std::make_unique<FlatSceneRenderer>(lab, cameras);
}

std::unique_ptr<SimulatedLab> make_simulated_lab(const LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings) {
  return std::make_unique<SimulatedLab>(lab, settings, make_scene_renderer(lab, cameras));
}

}  // namespace labo
