#include "core/subcommands.hpp"

#include <algorithm>
#include <iostream>
#include <span>

#include "core/config_reader.hpp"

namespace labo {

namespace {

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

void print_help(const Program& program) {
  std::cout << "usage: " << program.name << " <command> [options]\n\n" << program.about << "\n\ncommands:\n";
  for (const auto& c : program.commands) {
    std::string left = c.spec.name + (c.spec.positionals.empty() ? "" : " " + c.spec.positionals);
    std::cout << "  " << left << std::string(left.size() < 28 ? 28 - left.size() : 1, ' ') << c.spec.summary << "\n";
  }
  std::cout << "\nRun '" << program.name << " <command> --help' for a command's options.\n";
}

int run_one(const Program& program, const Subcommand& c, std::span<const std::string> rest) {
  const std::string who = program.name + " " + c.spec.name;
  try {
    const ParsedArgs parsed = parse_args(c.spec, rest);
    if (parsed.help) {
      std::cout << usage(c.spec, program.name);
      return 0;
    }
    return c.run(parsed);
  } catch (const UsageError& e) {
    std::cerr << who << ": " << e.what() << "\n";
    return 2;
  } catch (const ConfigError& e) {
    std::cerr << who << ": invalid configuration: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << who << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int run_program(const Program& program, const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    print_help(program);
    return args.empty() ? 2 : 0;
  }
  for (const auto& c : program.commands) {
    // A command's name may have several words ("bench planar"): match them all.
    if (const std::size_t words = matching_words(c.spec.name, args)) return run_one(program, c, std::span(args).subspan(words));
  }
  for (const auto& m : program.moved) {
    if (matching_words(m.prefix, args) == 0) continue;
    std::cerr << program.name << ": '" << m.prefix << "' commands are in " << m.binary << ": run '" << m.binary;
    for (const auto& a : args) std::cerr << " " << a;
    std::cerr << "'\n";
    return 2;
  }
  std::cerr << program.name << ": unknown command '" << args[0] << "' (see " << program.name << " --help)\n";
  return 2;
}

}  // namespace labo
