#pragma once
// `labodrone-bench sim realtime --mission inspect|find-teacher [--runs N] [--seed S] [--json]`:
// missions flown in real time through `labodrone serve`'s threads on the simulated lab
// (realtime_campaign.hpp), with each run's success and the control loop's timing.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& sim_realtime_command_spec();
int run_sim_realtime_command(const ParsedArgs& args);

}  // namespace labo::bench
