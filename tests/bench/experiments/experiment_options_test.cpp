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
  CHECK(o.nominal_factors.contains(sim::WorldFactor::Lens));
  CHECK_FALSE(options_of({"--vision", "real", "--world", "randomized"}).nominal_factors.contains(sim::WorldFactor::Lens));
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--calibrated-cameras"}), Catch::Contains("needs --world randomized"));
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--world", "nominal", "--calibrated-cameras"}),
                    Catch::Contains("needs --world randomized"));
  CHECK_THROWS_AS(options_of({"--calibrated-cameras"}), UsageError);
}

TEST_CASE("experiment options: world factors kept nominal or drawn alone, only in a randomized world") {
  using sim::WorldFactor;
  const std::vector<std::string> randomized{"--vision", "real", "--world", "randomized"};
  const auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> args = randomized;
    args.insert(args.end(), more.begin(), more.end());
    return options_of(args);
  };
  CHECK(options_of(randomized).nominal_factors.empty());
  const ExperimentOptions kept = with({"--nominal-factors", "lens,teacher"});
  CHECK(kept.nominal_factors.contains(WorldFactor::Lens));
  CHECK(kept.nominal_factors.contains(WorldFactor::Teacher));
  CHECK_FALSE(kept.nominal_factors.contains(WorldFactor::Drone));
  const ExperimentOptions only = with({"--world-factors", "lighting"});
  for (WorldFactor f : sim::kWorldFactors) CHECK(only.nominal_factors.contains(f) == (f != WorldFactor::Lighting));
  // --calibrated-cameras is the lens kept nominal.
  const ExperimentOptions calibrated = with({"--calibrated-cameras"});
  CHECK(calibrated.nominal_factors.contains(WorldFactor::Lens));
  CHECK_FALSE(calibrated.nominal_factors.contains(WorldFactor::Drone));

  CHECK_THROWS_WITH(with({"--nominal-factors", "lens,wind"}), Catch::Contains("'wind' is not a factor"));
  CHECK_THROWS_WITH(with({"--nominal-factors", "lens,"}), Catch::Contains("'' is not a factor"));
  CHECK_THROWS_WITH(with({"--world-factors", ""}), Catch::Contains("'' is not a factor"));
  CHECK_THROWS_WITH(with({"--nominal-factors", "lens", "--world-factors", "drone"}), Catch::Contains("one or the other"));
  CHECK_THROWS_WITH(with({"--calibrated-cameras", "--world-factors", "lens"}), Catch::Contains("give the lens in the list"));
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--nominal-factors", "lens"}), Catch::Contains("needs --world randomized"));
  CHECK_THROWS_WITH(options_of({"--vision", "real", "--world", "nominal", "--world-factors", "lens"}),
                    Catch::Contains("needs --world randomized"));
}
