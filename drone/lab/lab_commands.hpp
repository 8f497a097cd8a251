#pragma once
// `labodrone sim textures`: regenerates the procedural instrument panels and landing pattern
// (config/instruments/*.png) that config/lab.json refers to; `labodrone sim lab` validates a lab file.
#include "core/cli_args.hpp"

namespace labo::lab {

const CommandSpec& sim_textures_command_spec();
int run_sim_textures_command(const ParsedArgs& args);

const CommandSpec& sim_lab_command_spec();
int run_sim_lab_command(const ParsedArgs& args);

}  // namespace labo::lab
