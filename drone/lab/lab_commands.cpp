#include "drone/lab/lab_commands.hpp"

#include <iostream>

#include "drone/lab/instrument_panels.hpp"
#include "drone/lab/lab_description.hpp"
#include "core/source_tree.hpp"

namespace labo::lab {

const CommandSpec& sim_textures_command_spec() {
  static const CommandSpec spec{"sim textures",
                                "",
                                "Regenerate the procedural instrument panels and landing pattern (PNG).",
                                {{"--out", "DIR", "output folder (default: config/instruments of the source tree)"}},
                                0,
                                0};
  return spec;
}

int run_sim_textures_command(const ParsedArgs& args) {
  const std::filesystem::path dir =
      args.value_or("--out", (labo::source_root() / "config" / "instruments").string());
  for (const auto& p : write_instrument_templates(dir)) std::cout << "wrote " << p.string() << "\n";
  return 0;
}

const CommandSpec& sim_lab_command_spec() {
  static const CommandSpec spec{"sim lab",
                                "",
                                "Validate a lab description and print its objects.",
                                {{"--lab", "FILE", "lab description (default: config/lab.json)"}},
                                0,
                                0};
  return spec;
}

int run_sim_lab_command(const ParsedArgs& args) {
  const LabDescription lab = load_lab_description(args.value_or("--lab", default_lab_path().string()));
  std::cout << lab.source.string() << ": room " << lab.room.size().transpose() << " m, " << lab.benches.size()
            << " benches, " << lab.instruments.size() << " instruments, " << lab.cameras.size() << " cameras, teacher path of "
            << lab.teacher.waypoints.size() << " waypoints\n";
  for (const auto& i : lab.instruments) {
    std::cout << "  " << i.id << " (" << i.name << "): " << i.width_m << " x " << i.height_m << " m at "
              << i.T_world_object.translation().transpose() << "\n";
  }
  std::cout << "  platform " << lab.platform.id << ": top at " << lab.platform.T_world_object.translation().transpose() << "\n";
  return 0;
}

}  // namespace labo::lab
