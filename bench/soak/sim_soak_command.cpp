#include "bench/soak/sim_soak_command.hpp"

#include <iostream>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "bench/soak/soak_run.hpp"
#include "core/source_tree.hpp"
#include "server/http/heap_release.hpp"

namespace labo::bench {

const CommandSpec& sim_soak_command_spec() {
  static const CommandSpec spec{
      "sim soak",
      "",
      "labodrone serve on the simulated lab for M minutes under scripted clients and faults (link cuts, emulator "
      "restarts, low battery): checks that the server stays up, the drone lands safely, the recording replays and "
      "memory stays flat; a crash is reported with the 60 s before it (on the ground too), the estimate beside the truth.",
      {{"--minutes", "M", "how long the rounds of missions go on (default 30; 1-600)"},
       {"--seed", "N", "the simulated lab's and the audience's seed (default 1)"},
       {"--spectators", "N", "spectators at most at once (default 4)"},
       {"--slow-stall", "S", "how long the slow reader reads nothing at a time (default 60 s)"},
       {"--config", "FILE", "configuration (default: config/default.json); its students log in as <name>-pass"},
       {"--recording", "FILE", "where the driver records the flight (default: a temporary file, removed after)"},
       {"--log", "LEVEL", "the server's log level on stderr (default warn)"},
       {"--json", "", "print the summary as JSON"}},
      0,
      0};
  return spec;
}

int run_sim_soak_command(const ParsedArgs& args) {
  server::configure_server_heap();  // as `labodrone serve` runs: the soak measures its memory
  SoakOptions o;
  o.minutes = args.number_or("--minutes", 30.0, 1.0, 600.0);
  o.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  o.max_spectators = args.integer_or("--spectators", 4, 0, 64);
  o.slow_stall_s = args.number_or("--slow-stall", 60.0, 1.0, 3600.0);
  o.config_file = args.value_or("--config", (source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(o.config_file)) throw UsageError("--config " + o.config_file.string() + ": no such file");
  o.keep_recording = args.flag("--recording");
  o.recording = o.keep_recording ? std::filesystem::path(args.value_or("--recording", ""))
                                 : std::filesystem::temp_directory_path() /
                                       ("labodrone_soak_" + std::to_string(::getpid()) + ".laborec");
  try {
    o.log_level = parse_log_level(args.value_or("--log", "warn"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--log: ") + e.what());
  }

  const SoakSummary summary = run_soak(o);
  const std::vector<std::string> failures = soak_failures(summary, SoakLimits{});
  if (args.flag("--json")) {
    nlohmann::json j = to_json(summary, failures);
    j["minutes"] = o.minutes;
    j["seed"] = o.seed;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << to_text(summary, failures);
  }
  return failures.empty() ? 0 : 3;
}

}  // namespace labo::bench
