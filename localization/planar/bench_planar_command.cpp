#include <iostream>

#include <nlohmann/json.hpp>

#include "core/config_reader.hpp"
#include "localization/planar/perturbation_bench.hpp"
#include "localization/planar/planar_commands.hpp"

namespace labo {

namespace {

nlohmann::json to_json(const TrackerSweepStats& s) {
  return {{"convergence_percent", 100.0 * s.convergence_rate},
          {"final_corner_rms_px", s.mean_converged_rms_px},
          {"median_ms_per_call", s.median_ms},
          {"mean_ms_per_call", s.mean_ms},
          {"mean_iterations", s.mean_iterations}};
}

nlohmann::json sweep_json(const std::vector<PerturbationRow>& rows, const PerturbationSettings& settings) {
  nlohmann::json j;
  j["protocol"] = {{"template_px", settings.template_side_px},
                   {"scene_px", {settings.scene_width_px, settings.scene_height_px}},
                   {"trials_per_sigma", settings.trials},
                   {"converged_when", "tracker reports success and corner RMS <= 1 px"},
                   {"pixel_noise_grey_levels", settings.pixel_noise}};
  for (const auto& r : rows) {
    j["rows"].push_back({{"sigma_px", r.sigma_px}, {"ecc", to_json(r.ecc)}, {"ic", to_json(r.ic)}});
  }
  return j;
}

void print_sweep(const std::vector<PerturbationRow>& rows) {
  std::printf("corner-perturbation sweep (template 200 px, 640x480 scene)\n");
  std::printf("%6s | %9s %9s %9s | %9s %9s %9s\n", "sigma", "ECC conv%", "rms px", "ms", "IC conv%", "rms px", "ms");
  for (const auto& r : rows) {
    std::printf("%6.1f | %9.1f %9.3f %9.2f | %9.1f %9.3f %9.2f\n", r.sigma_px, 100 * r.ecc.convergence_rate,
                r.ecc.mean_converged_rms_px, r.ecc.median_ms, 100 * r.ic.convergence_rate, r.ic.mean_converged_rms_px,
                r.ic.median_ms);
  }
}

}  // namespace

const CommandSpec& bench_planar_command_spec() {
  static const CommandSpec spec{
      "bench planar",
      "",
      "planar tracking benchmark: corner-perturbation sweep (ECC vs LaboDrone's tracker) and simulated sequences",
      {{"--json", "", "print JSON instead of tables"},
       {"--trials", "N", "trials per sigma in the sweep (default 100)"},
       {"--part", "P", "sweep, sequences or all (default all)"},
       {"--noise", "G", "grey-level noise added to the sweep's scenes (default 2)"}},
      0,
      0};
  return spec;
}

int run_bench_planar_command(const ParsedArgs& args) {
  const bool json = args.flag("--json");
  const std::string part = args.value_or("--part", "all");
  if (part != "all" && part != "sweep" && part != "sequences") {
    throw UsageError("--part must be sweep, sequences or all, not '" + part + "'");
  }
  PerturbationSettings settings;
  settings.trials = args.integer_or("--trials", settings.trials, 1, 10000);
  settings.pixel_noise = args.number_or("--noise", settings.pixel_noise, 0.0, 50.0);
  const PlanarConfig config;
  nlohmann::json out;
  if (part != "sequences") {
    const auto rows = run_perturbation_sweep(settings, config);
    if (json) {
      out["perturbation_sweep"] = sweep_json(rows, settings);
    } else {
      print_sweep(rows);
    }
  }
  if (json) std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace labo
