#pragma once
// `labodrone-bench bench link`: times each per-packet / per-frame stage of the AR.Drone link.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_link_command_spec();
int run_bench_link_command(const ParsedArgs& args);

}  // namespace labo::bench
