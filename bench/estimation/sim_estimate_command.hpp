#pragma once
// `labodrone-bench sim estimate --seed S [--runs N] [--plant lab|surrogate] [--vision truth|real] [--json]
// [--fit-model]`: the state-estimation experiments in lockstep (estimation_experiment.hpp), with the
// targets beside each figure.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& sim_estimate_command_spec();
int run_sim_estimate_command(const ParsedArgs& args);

}  // namespace labo::bench
