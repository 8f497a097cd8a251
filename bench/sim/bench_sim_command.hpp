#pragma once
// `labodrone-bench bench sim`: the simulated lab's speed in lockstep (docs/sim.md quotes the figures).
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_sim_command_spec();
int run_bench_sim_command(const ParsedArgs& args);

}  // namespace labo::bench
