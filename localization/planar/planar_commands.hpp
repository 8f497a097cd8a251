#pragma once
// The planar subcommands of `labodrone`:
//   labodrone homography TEMPLATE IMAGE [--method auto|template|sift]   (exit 0 found, 3 not found, 2 bad input)
//   labodrone bench planar [--json] [--trials N] [--part sweep|sequences|all]
#include "core/cli_args.hpp"

namespace labo {

const CommandSpec& homography_command_spec();
int run_homography_command(const ParsedArgs& args);

const CommandSpec& bench_planar_command_spec();
int run_bench_planar_command(const ParsedArgs& args);

}  // namespace labo
