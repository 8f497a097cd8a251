// sim face-follow's options: the teacher's walking speed (the face-follow target is stated at 0.5 m/s).
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "bench/experiments/sim_commands.hpp"
#include "core/cli_args.hpp"

using namespace labo;

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
TEST_CASE("sim face-follow: --teacher-speed is refused out of range and without the lab's route") {
  CHECK(usage_error({"--route", "--teacher-speed", "9"}).find("--teacher-speed") != std::string::npos);
  CHECK(usage_error({"--vision", "real", "--teacher-speed", "-1"}).find("--teacher-speed") != std::string::npos);
  CHECK(usage_error({"--route", "--teacher-speed", "fast"}).find("--teacher-speed") != std::string::npos);
  // The model lab's back-and-forth has its own speed: the option would silently do nothing there.
  CHECK(usage_error({"--teacher-speed", "0.4"}).find("is for --route or --vision real") != std::string::npos);
}
