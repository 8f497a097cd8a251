#pragma once
// `labodrone-bench bench slam [--json] [--flight tour|yaw|approach|all] [--tour-seconds S] [--threaded]`
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_slam_command_spec();
int run_bench_slam_command(const ParsedArgs& args);

}  // namespace labo::bench
