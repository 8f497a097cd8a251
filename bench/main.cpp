// labodrone-bench: the lab bench of LaboDrone, one subcommand per benchmark or experiment, with the
// same words as they had in `labodrone` ("bench planar", "sim inspect"). Each has --help.
#include <string>
#include <vector>

#include "bench/batch_allocator.hpp"
#include "bench/estimation/sim_estimate_command.hpp"
#include "bench/experiments/bench_vision_command.hpp"
#include "bench/experiments/sim_commands.hpp"
#include "bench/face/bench_face_command.hpp"
#include "bench/face/bench_faces_command.hpp"
#include "bench/link/bench_link_command.hpp"
#include "bench/planar/bench_planar_command.hpp"
#include "bench/realtime/sim_realtime_command.hpp"
#include "bench/sim/bench_render_command.hpp"
#include "bench/sim/bench_sim_command.hpp"
#include "bench/slam/slam_bench_command.hpp"
#include "bench/soak/sim_soak_command.hpp"
#include "core/subcommands.hpp"

namespace {

labo::Program program() {
  using namespace labo;
  using namespace labo::bench;
  return {
      .name = "labodrone-bench",
      .about = "LaboDrone's lab bench: benchmarks of each stage and the paper's experiments, in lockstep on the\n"
               "simulated lab. The product is labodrone.",
      .commands =
          {
              {bench_link_command_spec(), run_bench_link_command},
              {bench_planar_command_spec(), run_bench_planar_command},
              {bench_slam_command_spec(), run_bench_slam_command},
              {face_bench_command_spec(), run_face_bench_command},
              {faces_bench_command_spec(), run_faces_bench_command},
              {bench_vision_command_spec(), run_bench_vision_command},
              {bench_render_command_spec(), run_bench_render_command},
              {bench_sim_command_spec(), run_bench_sim_command},
              {sim_estimate_command_spec(), run_sim_estimate_command},
              {sim_inspect_command_spec(), run_sim_inspect_command},
              {sim_perturb_command_spec(), run_sim_perturb_command},
              {sim_face_follow_command_spec(), run_sim_face_follow_command},
              {sim_compare_slam_command_spec(), run_sim_compare_slam_command},
              {sim_realtime_command_spec(), run_sim_realtime_command},
              {sim_soak_command_spec(), run_sim_soak_command},
          },
      .moved = {},
  };
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  // Every command here but the soak is a batch run: reuse freed memory (bench/batch_allocator.hpp).
  // The soak measures the server's memory as `labodrone serve` has it, with glibc's defaults.
  const bool soak = args.size() >= 2 && args[0] == "sim" && args[1] == "soak";
  if (!soak) labo::bench::keep_freed_memory_for_batch_runs();
  return labo::run_program(program(), args);
}
