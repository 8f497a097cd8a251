#pragma once
// `labodrone bench sim`: the simulated lab's speed in lockstep (docs/sim.md quotes the figures).
#include "core/cli_args.hpp"
#include "drone/sim/head_model.hpp"

namespace labo {

const CommandSpec& bench_sim_command_spec();
// The teacher's face comes from the caller (`load_head`, localization/face/teacher_head.hpp).
int run_bench_sim_command(const ParsedArgs& args, const TeacherHeadLoader& load_head);

}  // namespace labo
