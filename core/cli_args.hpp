#pragma once
// Command-line parsing for the `labodrone` subcommands: declared options, positionals, --help.
// Unknown flags and missing values throw UsageError, which main() turns into exit status 2.
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace labo {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OptionSpec {
  std::string name;        // "--port"
  std::string value_name;  // "N"; empty for a flag without value
  std::string help;
};

struct CommandSpec {
  std::string name;         // "serve"
  std::string positionals;  // "TEMPLATE IMAGE", for the usage line
  std::string summary;
  std::vector<OptionSpec> options;
  int min_positionals = 0;
  int max_positionals = 0;
};

class ParsedArgs {
 public:
  bool help = false;
  std::vector<std::string> positionals;

  bool flag(const std::string& name) const { return values_.contains(name); }
  std::optional<std::string> value(const std::string& name) const;
  std::string value_or(const std::string& name, const std::string& fallback) const;
  // Integer and number values; throw UsageError naming the option and the range.
  int integer_or(const std::string& name, int fallback, int min, int max) const;
  double number_or(const std::string& name, double fallback, double min, double max) const;

  std::map<std::string, std::string> values_;
};

ParsedArgs parse_args(const CommandSpec& spec, std::span<const std::string> args);
// `program` is the binary the command belongs to ("labodrone", "labodrone-bench").
std::string usage(const CommandSpec& spec, const std::string& program = "labodrone");

}  // namespace labo
