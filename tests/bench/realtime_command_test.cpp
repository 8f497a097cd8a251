#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "bench/realtime/sim_realtime_command.hpp"

using namespace labo;
using namespace labo::bench;

namespace {
int run(const std::vector<std::string>& args) {
  return run_sim_realtime_command(parse_args(sim_realtime_command_spec(), args));
}
}  // namespace

TEST_CASE("sim realtime: bad options are refused naming what was expected") {
  CHECK_THROWS_WITH(run({"--mission", "dance"}), Catch::Contains("--mission must be inspect or find-teacher"));
  CHECK_THROWS_WITH(run({"--runs", "0"}), Catch::Contains("--runs"));
  CHECK_THROWS_WITH(run({"--timeout", "1"}), Catch::Contains("--timeout"));
  CHECK_THROWS_WITH(run({"--config", "/nonexistent/config.json"}), Catch::Contains("no such file"));
  CHECK_THROWS_WITH(run({"--in-a-row", "0"}), Catch::Contains("--in-a-row"));
  CHECK_THROWS_WITH(run({"--trace", "/nonexistent/dir/trace.csv"}), Catch::Contains("--trace /nonexistent/dir/trace.csv: cannot write"));
}
