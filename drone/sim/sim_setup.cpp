#include "drone/sim/sim_setup.hpp"

#include "core/config_reader.hpp"
#include "drone/sim/lab_renderer.hpp"

namespace labo::sim {

using ardrone2::ArdroneEmulatorSettings;
using ardrone2::read_ardrone_emulator_settings;
using lab::LabDescription;
using lab::load_lab_description;


std::unique_ptr<SceneRenderer> make_scene_renderer(const LabDescription& lab, const CamerasConfig& cameras,
                                                   std::optional<TexturedHeadModel> head, unsigned seed,
                                                   const CameraMounts& mounts) {
  return make_lab_renderer(lab, cameras, std::move(head), seed, {}, mounts);
}

std::unique_ptr<SimulatedLab> make_simulated_lab(const LabDescription& lab, const CamerasConfig& cameras,
                                                 const SimulatedLabSettings& settings, std::optional<TexturedHeadModel> head) {
  return std::make_unique<SimulatedLab>(lab, settings,
                                        make_scene_renderer(lab, cameras, std::move(head), static_cast<unsigned>(settings.seed)));
}

std::unique_ptr<SimulatedLab> make_simulated_lab(const SimWorld& world, std::optional<TexturedHeadModel> head) {
  return std::make_unique<SimulatedLab>(
      world.lab, world.settings,
      make_scene_renderer(world.lab, world.cameras, std::move(head), static_cast<unsigned>(world.settings.seed), world.mounts));
}

SimInputs load_sim_inputs(const std::filesystem::path& config_file, const std::optional<std::filesystem::path>& lab_file) {
  const ConfigDocument doc = ConfigDocument::load(config_file);
  const ConfigReader root = doc.root();
  SimInputs in;
  in.cameras = read_cameras_config_or_stock(root);
  in.emulator = root.has("emulator") ? read_ardrone_emulator_settings(root.object("emulator")) : ArdroneEmulatorSettings{};
  in.sim = read_sim_config_of(root);
  in.lab = load_lab_description(lab_file ? *lab_file
                                         : (config_file.parent_path() / root.string_or("lab", "lab.json")).lexically_normal());
  return in;
}

}  // namespace labo::sim
