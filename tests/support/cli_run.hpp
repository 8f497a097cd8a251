#pragma once
// Runs a subcommand's function as `labodrone` would, with std::cout and std::cerr captured (and put
// back even when it throws), for tests of commands that print an answer and exit 0 or 2. Tests only.
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/cli_args.hpp"

namespace labo::test {

struct CliRun {
  int code = -1;
  std::string out, err;
};

inline CliRun run_command(int (*fn)(const ParsedArgs&), const CommandSpec& spec, const std::vector<std::string>& argv) {
  std::ostringstream out, err;
  struct Restore {
    std::streambuf* cout_buf;
    std::streambuf* cerr_buf;
    ~Restore() {
      std::cout.rdbuf(cout_buf);
      std::cerr.rdbuf(cerr_buf);
    }
  } restore{std::cout.rdbuf(out.rdbuf()), std::cerr.rdbuf(err.rdbuf())};
  CliRun r;
  r.code = fn(parse_args(spec, argv));
  r.out = out.str();
  r.err = err.str();
  return r;
}

}  // namespace labo::test
