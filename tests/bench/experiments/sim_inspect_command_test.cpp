// sim inspect's options are refused before any flight, naming what was expected.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "bench/experiments/sim_commands.hpp"
#include "core/cli_args.hpp"

using namespace labo;
using namespace labo::bench;

namespace {
std::string usage_error(const std::vector<std::string>& args) {
  try {
    run_sim_inspect_command(parse_args(sim_inspect_command_spec(), args));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("sim inspect: --in-a-row is bounded and --instrument must be in the lab") {
  CHECK(usage_error({"--in-a-row", "0"}).find("--in-a-row") != std::string::npos);
  CHECK(usage_error({"--in-a-row", "21"}).find("--in-a-row") != std::string::npos);
  CHECK(usage_error({"--in-a-row", "many"}).find("--in-a-row") != std::string::npos);
  CHECK(usage_error({"--instrument", "kettle"}).find("--instrument kettle: no such instrument") != std::string::npos);
}
