#pragma once
// The command line of LaboDrone's binaries: one subcommand per job, named by one or more words
// ("serve", "bench planar"), each with its own CommandSpec and --help. Exit status: 0 success,
// 2 bad arguments or invalid input (UsageError, ConfigError), 1 any other failure, or what the
// subcommand returns.
#include <functional>
#include <string>
#include <vector>

#include "core/cli_args.hpp"

namespace labo {

struct Subcommand {
  const CommandSpec& spec;
  std::function<int(const ParsedArgs&)> run;
};

// A command that lives in another binary: its leading words and where it went.
struct MovedCommand {
  std::string prefix;  // "bench", "sim inspect"
  std::string binary;  // "labodrone-bench"
};

struct Program {
  std::string name;   // "labodrone"
  std::string about;  // one paragraph for --help
  std::vector<Subcommand> commands;
  std::vector<MovedCommand> moved;
};

// Runs the subcommand that `args` (argv without the program name) names; prints usage on --help or
// no arguments, and a one-line reason on stderr for every refusal.
int run_program(const Program& program, const std::vector<std::string>& args);

}  // namespace labo
