#pragma once
// The lockstep experiments of the paper's §6 as `labodrone-bench sim ...` subcommands. Each takes
// --seed, --runs, --json and --out DIR (CSV of every run's samples and an SVG plot of the first run,
// plus a summary), and prints its figures against their targets.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& sim_inspect_command_spec();
int run_sim_inspect_command(const ParsedArgs& args);
const CommandSpec& sim_perturb_command_spec();
int run_sim_perturb_command(const ParsedArgs& args);
const CommandSpec& sim_face_follow_command_spec();
int run_sim_face_follow_command(const ParsedArgs& args);
const CommandSpec& sim_compare_slam_command_spec();
int run_sim_compare_slam_command(const ParsedArgs& args);

}  // namespace labo::bench
