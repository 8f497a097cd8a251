#include "control/experiments/experiment_common.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "control/experiments/flight_plot.hpp"
#include "control/experiments/model_lab.hpp"
#include "core/config_reader.hpp"
#include "core/source_tree.hpp"

namespace labo {

std::vector<OptionSpec> experiment_option_specs() {
  return {{"--seed", "N", "first random seed (default 1); run i uses seed + i"},
          {"--runs", "N", "number of seeded runs (default 1)"},
          {"--json", "", "print the summary as JSON"},
          {"--out", "DIR", "write CSV per run, an SVG plot of the first run and summary.json"},
          {"--config", "FILE", "configuration to read the control section from (default config/default.json)"}};
}

ExperimentOptions read_experiment_options(const ParsedArgs& args) {
  ExperimentOptions o;
  o.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  o.runs = args.integer_or("--runs", 1, 1, 10000);
  o.json = args.flag("--json");
  o.config = args.value_or("--config", (labo::source_root() / "config" / "default.json").string());
  if (!std::filesystem::exists(o.config)) throw UsageError("--config " + o.config.string() + ": no such file");
  if (auto dir = args.value("--out")) {
    o.out = *dir;
    std::error_code ec;
    std::filesystem::create_directories(*o.out, ec);
    if (ec) throw UsageError("--out " + *dir + ": cannot create the folder: " + ec.message());
  }
  return o;
}

FlightStackSetup experiment_setup(const ExperimentOptions& options) {
  FlightStackSetup setup;
  setup.lab = model_lab();
  const ConfigDocument doc = ConfigDocument::load(options.config);
  const ConfigReader root = doc.root();
  if (root.has("control")) setup.control = read_control_config(root.object("control"));
  if (root.has("estimation")) setup.estimation = read_estimation_config(root.object("estimation"));
  if (root.has("vision")) setup.vision = read_vision_thresholds(root.object("vision"));
  // The quadrotor and perception models deliver navdata and vision results without link latency and
  // act on commands at once: the estimator's delay compensation must not shift them.
  setup.estimation.video_delay_s = 0;
  setup.estimation.navdata_delay_s = 0;
  setup.estimation.control_delay_s = 0;
  return setup;
}

void write_run_outputs(const ExperimentOptions& options, const std::string& name, int index, const LockstepFlight& flight) {
  if (!options.out) return;
  const std::string stem = name + "_seed" + std::to_string(options.seed + static_cast<unsigned>(index));
  write_flight_csv(*options.out / (stem + ".csv"), flight.samples());
  if (index == 0)
    write_flight_svg(*options.out / (stem + ".svg"), flight.samples(),
                     "labodrone sim " + name + " (seed " + std::to_string(options.seed) + "; quadrotor model, perception model)");
}

void report(const ExperimentOptions& options, const std::string& name, const nlohmann::json& summary,
            const std::vector<std::string>& text_lines) {
  if (options.out) {
    std::ofstream f(*options.out / (name + "_summary.json"));
    f << summary.dump(2) << "\n";
  }
  if (options.json) {
    std::cout << summary.dump(2) << "\n";
    return;
  }
  for (const auto& line : text_lines) std::cout << line << "\n";
}

double rms(const std::vector<double>& v) {
  if (v.empty()) return 0;
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5));
  return v[i];
}

double centre_offset_fraction(const Eigen::Vector3d& p_cam, const CameraIntrinsics& k) {
  const double u = k.fx * p_cam.x() / p_cam.z() + k.cx, v = k.fy * p_cam.y() / p_cam.z() + k.cy;
  return std::hypot(u - 0.5 * k.width, v - 0.5 * k.height) / k.width;
}

}  // namespace labo
