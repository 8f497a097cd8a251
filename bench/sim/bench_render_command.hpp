#pragma once
// `labodrone-bench bench render`: the simulated lab renderer's time per frame (median, p95) along a
// flight through the lab, for each camera, sharp and with motion blur and noise.
// docs/sim_rendering.md.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_render_command_spec();
int run_bench_render_command(const ParsedArgs& args);

}  // namespace labo::bench
