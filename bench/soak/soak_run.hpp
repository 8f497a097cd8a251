#pragma once
// A soak of `labodrone serve --drone sim` under faults (bench/soak/): the server in-process
// (SoakServer), students taking turns at missions (SoakScript), spectators and a slow reader
// (SoakAudience), the observer (SoakWatch); then the recording checked and the summary made.
#include <filesystem>
#include <string>

#include "bench/soak/soak_report.hpp"
#include "core/log.hpp"

namespace labo::bench {

struct SoakOptions {
  std::filesystem::path config_file;  // its students log in with the demo password "<name>-pass"
  double minutes = 30;
  unsigned seed = 1;                  // the simulated lab's and the audience's
  int max_spectators = 4;
  double slow_stall_s = 60;           // how long the slow reader reads nothing at a time
  std::filesystem::path recording;    // where the driver records the flight (removed unless kept)
  bool keep_recording = false;
  LogLevel log_level = LogLevel::Warn;
};

// Throws ConfigError for a bad configuration, std::runtime_error when a student cannot log in.
SoakSummary run_soak(const SoakOptions& options);

}  // namespace labo::bench
