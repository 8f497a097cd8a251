// labodrone: one binary, one subcommand per job. `labodrone --help` lists them; each has --help.
// Exit status: 0 success, 2 bad arguments or invalid input, others as each subcommand documents.
#include <algorithm>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "control/experiments/bench_vision_command.hpp"
#include "control/experiments/sim_commands.hpp"
#include "core/cli_args.hpp"
#include "core/config_reader.hpp"
#include "drone/ardrone2/bench_command.hpp"
#include "drone/ardrone2/inspect_commands.hpp"
#include "localization/planar/planar_commands.hpp"
#include "localization/slam/bench/slam_bench_command.hpp"
#include "localization/face/face_commands.hpp"
#include "server/estimation_vision.hpp"
#include "server/hash_password_command.hpp"
#include "localization/estimation/eval/sim_estimate_command.hpp"
#include "server/serve_command.hpp"
#include "drone/lab/lab_commands.hpp"
#include "drone/sim/bench_sim_command.hpp"
#include "drone/sim/emulate_command.hpp"
#include "drone/sim/render_commands.hpp"
#include "server/batch_allocator.hpp"
#include "localization/face/teacher_head.hpp"

namespace {

// The simulated teacher's face for the commands that run the simulated lab (drone/ cannot call
// localization/).
labo::TexturedHeadModel teacher_head(const labo::LabDescription& lab) { return labo::face::load_lab_teacher_head(lab); }

struct Subcommand {
  const labo::CommandSpec& spec;
  int (*run)(const labo::ParsedArgs&);
};

std::vector<Subcommand> subcommands() {
  return {
      {labo::serve_command_spec(), labo::run_serve_command},
      {labo::navdata_command_spec(), labo::run_navdata_command},
      {labo::video_command_spec(), labo::run_video_command},
      {labo::homography_command_spec(), labo::run_homography_command},
      {labo::bench_planar_command_spec(), labo::run_bench_planar_command},
      {labo::bench_slam_command_spec(), labo::run_bench_slam_command},
      {labo::face_bench_command_spec(), labo::run_face_bench_command},
      {labo::face_register_command_spec(), labo::run_face_register_command},
      {labo::bench_link_command_spec(), labo::run_bench_link_command},
      {labo::bench_vision_command_spec(), labo::run_bench_vision_command},
      {labo::hash_password_command_spec(), labo::run_hash_password_command},
      {labo::sim_inspect_command_spec(), labo::run_sim_inspect_command},
      {labo::sim_perturb_command_spec(), labo::run_sim_perturb_command},
      {labo::sim_face_follow_command_spec(), labo::run_sim_face_follow_command},
      {labo::sim_textures_command_spec(), labo::run_sim_textures_command},
      {labo::sim_lab_command_spec(), labo::run_sim_lab_command},
      {labo::sim_render_command_spec(),
       [](const labo::ParsedArgs& a) { return labo::run_sim_render_command(a, teacher_head); }},
      {labo::bench_render_command_spec(),
       [](const labo::ParsedArgs& a) { return labo::run_bench_render_command(a, teacher_head); }},
      {labo::emulate_command_spec(), [](const labo::ParsedArgs& a) { return labo::run_emulate_command(a, teacher_head); }},
      {labo::bench_sim_command_spec(), [](const labo::ParsedArgs& a) { return labo::run_bench_sim_command(a, teacher_head); }},
      {labo::sim_compare_slam_command_spec(), labo::run_sim_compare_slam_command},
      {labo::sim_estimate_command_spec(),
       [](const labo::ParsedArgs& a) { return labo::run_sim_estimate_command(a, labo::real_vision_pipelines); }},
  };
}

// How many leading arguments spell the command's name, 0 when they do not.
std::size_t matching_words(const std::string& name, const std::vector<std::string>& args) {
  std::size_t pos = 0, words = 0;
  while (pos <= name.size()) {
    const std::size_t end = std::min(name.find(' ', pos), name.size());
    if (words >= args.size() || args[words] != name.substr(pos, end - pos)) return 0;
    ++words;
    pos = end + 1;
  }
  return words;
}

void print_help(const std::vector<Subcommand>& commands) {
  std::cout << "usage: labodrone <command> [options]\n\n"
               "LaboDrone flies an AR.Drone 2.0 (or the simulated lab) through a remote electronics lab.\n\n"
               "commands:\n";
  for (const auto& c : commands) {
    std::string left = c.spec.name + (c.spec.positionals.empty() ? "" : " " + c.spec.positionals);
    std::cout << "  " << left << std::string(left.size() < 28 ? 28 - left.size() : 1, ' ') << c.spec.summary << "\n";
  }
  std::cout << "\nRun 'labodrone <command> --help' for a command's options.\n";
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const auto commands = subcommands();
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    print_help(commands);
    return args.empty() ? 2 : 0;
  }
  for (const auto& c : commands) {
    // A command's name may have several words ("bench planar"): match them all.
    const std::size_t words = matching_words(c.spec.name, args);
    if (words == 0) continue;
    try {
      const labo::ParsedArgs parsed = labo::parse_args(c.spec, std::span(args).subspan(words));
      if (parsed.help) {
        std::cout << labo::usage(c.spec);
        return 0;
      }
      // Batch commands reuse freed memory (server/batch_allocator.hpp): SIFT's per-call pyramid
      // otherwise costs a fifth of a real-vision simulation's CPU in page faults.
      if (c.spec.name.starts_with("sim ") || c.spec.name.starts_with("bench ")) labo::keep_freed_memory_for_batch_runs();
      return c.run(parsed);
    } catch (const labo::UsageError& e) {
      std::cerr << "labodrone " << c.spec.name << ": " << e.what() << "\n";
      return 2;
    } catch (const labo::ConfigError& e) {
      std::cerr << "labodrone " << c.spec.name << ": invalid configuration: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "labodrone " << c.spec.name << ": " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "labodrone: unknown command '" << args[0] << "' (see labodrone --help)\n";
  return 2;
}
