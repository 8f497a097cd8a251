#pragma once
// What the `labodrone sim ...` experiments share: options, the setup, output files, statistics.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "control/experiments/lockstep_flight.hpp"
#include "core/cli_args.hpp"

namespace labo {

struct ExperimentOptions {
  unsigned seed = 1;
  int runs = 1;
  bool json = false;
  std::optional<std::filesystem::path> out;
  std::filesystem::path config;  // --config, default config/default.json
};

std::vector<OptionSpec> experiment_option_specs();
ExperimentOptions read_experiment_options(const ParsedArgs& args);
// The setup the experiments fly: the model lab, config/default.json's control/estimation/vision.
FlightStackSetup experiment_setup(const ExperimentOptions& options);
// Writes run `index`'s CSV (and its SVG for the first run) under --out.
void write_run_outputs(const ExperimentOptions& options, const std::string& name, int index, const LockstepFlight& flight);
// Writes summary.json under --out, prints JSON (--json) or the text lines.
void report(const ExperimentOptions& options, const std::string& name, const nlohmann::json& summary,
            const std::vector<std::string>& text_lines);

double rms(const std::vector<double>& v);
double percentile(std::vector<double> v, double p);
// Pixel offset of a camera-frame point from the image centre, as a fraction of the image width.
double centre_offset_fraction(const Eigen::Vector3d& p_cam, const CameraIntrinsics& k);

}  // namespace labo
