#pragma once
// `labodrone-bench bench faces`: Table 1 per face and pooled over the face gallery (the astronaut and
// the Solvay 1927 photograph's faces), each face registered from its own frontal frames. docs/face.md.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& faces_bench_command_spec();
int run_faces_bench_command(const ParsedArgs& args);

}  // namespace labo::bench
