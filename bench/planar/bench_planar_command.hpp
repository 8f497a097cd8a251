#pragma once
// `labodrone-bench bench planar [--json] [--trials N] [--part sweep|sequences|all]`: the trackers'
// convergence sweep (ECC vs the inverse-compositional tracker) and the rendered flight sequences.
// docs/planar.md.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_planar_command_spec();
int run_bench_planar_command(const ParsedArgs& args);

}  // namespace labo::bench
