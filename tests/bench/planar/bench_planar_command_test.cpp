#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/cli_args.hpp"
#include "bench/planar/bench_planar_command.hpp"

using namespace labo;
using namespace labo::bench;

namespace {

std::string usage_error(const std::vector<std::string>& args) {
  try {
    run_bench_planar_command(parse_args(bench_planar_command_spec(), args));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Both refusals come before any benchmarking (they would otherwise cost minutes of CPU first).
TEST_CASE("bench planar: --frames-csv is refused with the reason when it cannot be written or has no frames") {
  const std::string unwritable = usage_error({"--part", "sequences", "--frames-csv", "/nonexistent-dir/frames.csv"});
  CHECK(unwritable.find("--frames-csv: cannot write '/nonexistent-dir/frames.csv'") != std::string::npos);
  const std::string sweep_only = usage_error({"--part", "sweep", "--frames-csv", "frames.csv"});
  CHECK(sweep_only.find("--frames-csv needs the sequences") != std::string::npos);
}

TEST_CASE("bench planar: --h264-kbps outside 100-20000 or not a number is refused, naming the option") {
  for (const std::string bad : {"50", "20001", "fast", "-1000"}) {
    const std::string reason = usage_error({"--part", "sequences", "--h264-kbps", bad});
    INFO(bad << ": " << reason);
    CHECK(reason.find("--h264-kbps") != std::string::npos);
  }
}

TEST_CASE("bench planar: --h264-seeds outside 1-64, not a number, or without the sequences is refused, naming the option") {
  for (const std::string bad : {"0", "65", "two", "-3"}) {
    const std::string reason = usage_error({"--part", "sequences", "--h264-seeds", bad});
    INFO(bad << ": " << reason);
    CHECK(reason.find("--h264-seeds: '" + bad + "' is not an integer in [1, 64]") != std::string::npos);
  }
  const std::string sweep_only = usage_error({"--part", "sweep", "--h264-seeds", "4"});
  CHECK(sweep_only.find("--h264-seeds needs the sequences") != std::string::npos);
}
