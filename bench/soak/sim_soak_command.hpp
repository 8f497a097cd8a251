#pragma once
// `labodrone-bench sim soak [--minutes M] [--seed S] [--config FILE] [--json]`: `labodrone serve
// --drone sim` in-process for M minutes with scripted students, spectators and a slow reader over
// real HTTP and WebSocket, link cuts, emulator restarts and a nearly empty battery in the middle
// (bench/soak/soak_run.hpp); prints the summary and exits 3 when a check failed.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& sim_soak_command_spec();
int run_sim_soak_command(const ParsedArgs& args);

}  // namespace labo::bench
