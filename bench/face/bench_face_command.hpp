#pragma once
// `labodrone-bench bench face`: the face pose methods (the paper's Table 1) on rendered head-pose
// sequences with a known pose. docs/face.md.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& face_bench_command_spec();
int run_face_bench_command(const ParsedArgs& args);

}  // namespace labo::bench
