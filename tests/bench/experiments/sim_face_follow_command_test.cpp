// sim face-follow's options: nothing about the teacher's walk is an option (the flight software is
// never given it, and the simulated teacher's walk is the world's: drawn per seed or the lab file's).
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
    run_sim_face_follow_command(parse_args(sim_face_follow_command_spec(), args));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// Each refusal comes before any flight.
TEST_CASE("sim face-follow: the teacher's speed and route are no options, --walk is bounded") {
  CHECK(usage_error({"--teacher-speed", "0.4"}).find("--teacher-speed") != std::string::npos);
  CHECK(usage_error({"--route"}).find("--route") != std::string::npos);
  CHECK(usage_error({"--walk", "0"}).find("--walk") != std::string::npos);
  CHECK(usage_error({"--walk", "long"}).find("--walk") != std::string::npos);
}
