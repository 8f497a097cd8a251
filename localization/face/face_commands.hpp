#pragma once
// `labodrone bench face` (Table 1 on rendered head-pose sequences) and `labodrone face register`
// (fit a person's CANDIDE-3 shape from a frontal picture and store it).
#include "core/cli_args.hpp"

namespace labo {

const CommandSpec& face_bench_command_spec();
int run_face_bench_command(const ParsedArgs& args);

const CommandSpec& face_register_command_spec();
int run_face_register_command(const ParsedArgs& args);

}  // namespace labo
