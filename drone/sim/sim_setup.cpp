#include "drone/sim/sim_setup.hpp"

#include "drone/sim/lab_renderer.hpp"

namespace labo {

std::unique_ptr<SceneRenderer> make_scene_renderer(const LabDescription& lab, const CamerasConfig& cameras,
                                                   std::optional<TexturedHeadModel> head, unsigned seed) {
  return make_lab_renderer(lab, cameras, std::move(head), seed);
}

std::unique_ptr<SimulatedLab> make_simulated_lab(const LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings, std::optional<TexturedHeadModel> head) {
  return std::make_unique<SimulatedLab>(lab, settings,
                                        make_scene_renderer(lab, cameras, std::move(head), static_cast<unsigned>(settings.seed)));
}

}  // namespace labo
