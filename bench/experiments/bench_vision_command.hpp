#pragma once
// `labodrone-bench bench vision`: the per-frame cost of each vision front-end flight control runs
// (localization/fusion/vision_front_end.hpp) on rendered frames - planar detection far and near, panel and
// platform tracking, SLAM tracking, face tracking - as median, p95 and max wall time per frame.
#include "core/cli_args.hpp"

namespace labo::bench {

const CommandSpec& bench_vision_command_spec();
int run_bench_vision_command(const ParsedArgs& args);

}  // namespace labo::bench
