#pragma once
// What the `labodrone-bench sim ...` experiments share: options, the setup, output files, statistics.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include <memory>

#include "bench/experiments/experiment_flight.hpp"
#include "bench/experiments/lockstep_vision_worker.hpp"
#include "core/cli_args.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/sim/sim_tello_link.hpp"
#include "drone/sim/sim_world.hpp"

namespace labo::bench {

using sim::SimConfig;
using sim::SimTelloLink;
using sim::SimTelloSettings;
using sim::TexturedHeadModel;
using sim::WorldMode;
using sim::WorldRanges;


struct ExperimentOptions {
  unsigned seed = 1;
  int runs = 1;
  bool json = false;
  std::optional<std::filesystem::path> out;
  std::filesystem::path config;  // --config, default config/default.json
  bool real_vision = false;      // --vision real: the simulated lab, rendered cameras, real front-ends
  std::optional<double> video_fps;  // --fps, with --vision real (default: the sim section's 30)
  // --vision-latency worker: the server's vision worker modelled (lockstep_vision_worker.hpp).
  std::optional<VisionLatencyModel> vision_latency;
  int jobs = 1;  // --jobs: seeded runs flown at once on that many threads (seed_runner.hpp)
  // --world (with --vision real): the simulated lab's world, replacing the config's sim.world.
  std::optional<WorldMode> world;
  // --calibrated-cameras (with --world randomized): each drawn world's cameras have the configured
  // intrinsics and distortion exactly, as a drone whose cameras were calibrated one by one; the rest
  // is drawn as before (their mounting tilt too).
  sim::WorldFactorSet nominal_factors;  // --nominal-factors, --world-factors, or the lens with --calibrated-cameras
  // --drone-model tello (with --vision real): the lab flown as a Tello (SimTelloLink), the flight
  // software set up for one (the Tello's camera and estimation section, docs/tello.md).
  bool tello = false;
};

std::vector<OptionSpec> experiment_option_specs();
// --vision model|real, --fps and --vision-latency, for the experiments that can fly the simulated lab.
std::vector<OptionSpec> real_vision_option_specs();
// --jobs N, for the experiments whose runs fly in parallel (inspect, perturb, face-follow).
OptionSpec jobs_option_spec();
ExperimentOptions read_experiment_options(const ParsedArgs& args);

// What the experiments fly: the setup (config's control/estimation/vision sections; the model lab,
// or with --vision real the config's lab file, cameras and vision front-ends) and, with --vision
// real, the lab description the simulated lab is built from.
struct Experiment {
  control::FlightStackSetup setup;
  std::optional<lab::LabDescription> lab;       // --vision real: the lab the simulated lab is built from
  SimConfig sim;                           // its "sim" section (lab and link settings)
  std::optional<TexturedHeadModel> head;   // the teacher's face, when the experiment looks for it
  std::optional<VisionLatencyModel> vision_latency;  // --vision-latency worker
  // What a randomized world draws: the teacher's walk only for the experiments that follow the face.
  WorldRanges world_ranges;
  std::optional<SimTelloSettings> tello;   // --drone-model tello: the lockstep Tello's settings
};
// `with_face`: load the face front-end (find teacher) with --vision real.
Experiment make_experiment(const ExperimentOptions& options, bool with_face);
// One run's flight: LockstepFlight (models) or, with --vision real, SimLabFlight (the lab's and the
// link's seeds set to `seed`).
std::unique_ptr<ExperimentFlight> make_flight(const Experiment& experiment, unsigned seed);
// The world the runs fly in, for summaries: "nominal" or "randomized", "none" for the models.
std::string world_name(const Experiment& experiment);
// A run's world (world_report.hpp) up to now, or null for the models' flights.
nlohmann::json run_world_json(const ExperimentFlight& flight);
// Writes run `index`'s CSV (and its SVG for the first run) under --out.
void write_run_outputs(const ExperimentOptions& options, const std::string& name, int index, const ExperimentFlight& flight);
// Writes summary.json under --out, prints JSON (--json) or the text lines.
void report(const ExperimentOptions& options, const std::string& name, const nlohmann::json& summary,
            const std::vector<std::string>& text_lines);

// What the runs fly: the vehicle, the perception and the estimator, for the summaries.
std::string real_vision_note(const ExperimentOptions& options);
// A printf-style line of figures for the text summaries.
std::string fmt(const char* format, double a, double b = 0, double c = 0);

double rms(const std::vector<double>& v);
double percentile(std::vector<double> v, double p);
// Pixel offset of a camera-frame point from the image centre, as a fraction of the image width.
double centre_offset_fraction(const Eigen::Vector3d& p_cam, const CameraIntrinsics& k);

}  // namespace labo::bench
