#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "bench/experiments/experiment_common.hpp"
#include "bench/experiments/sim_commands.hpp"
#include "core/cli_args.hpp"

using namespace labo;
using namespace labo::bench;

namespace {
ExperimentOptions options_of(std::vector<std::string> args) {
  return read_experiment_options(parse_args(sim_face_follow_command_spec(), args));
}
}  // namespace

TEST_CASE("experiment options: calibrated cameras only in a randomized world") {
  const ExperimentOptions o = options_of({"--vision", "real", "--world", "randomized", "--calibrated-cameras"});
  CHECK(o.calibrated_cameras);
  CHECK_FALSE(options_of({"--vision", "real", "--world", "randomized"}).calibrated_cameras);
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--calibrated-cameras"}), Catch::Contains("needs --world randomized"));
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--world", "nominal", "--calibrated-cameras"}),
                    Catch::Contains("needs --world randomized"));
  CHECK_THROWS_AS(options_of({"--calibrated-cameras"}), UsageError);
}
