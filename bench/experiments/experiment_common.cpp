#include "bench/experiments/experiment_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "bench/experiments/flight_plot.hpp"
#include "bench/experiments/lockstep_flight.hpp"
#include "bench/experiments/model_lab.hpp"
#include "bench/experiments/sim_lab_flight.hpp"
#include "bench/experiments/world_report.hpp"
#include "localization/fusion/front_end_settings.hpp"
#include "core/camera_config.hpp"
#include "core/config_reader.hpp"
#include "localization/face/teacher_head.hpp"
#include "core/source_tree.hpp"
#include "drone/tello/tello_config.hpp"

namespace labo::bench {

using lab::LabDescription;
using lab::load_lab_description;
using tello::TelloConfig;
using tello::read_tello_config_of;
using tello::tello_cameras;

using sim::LabRenderer;
using sim::SimConfig;
using sim::SimDroneLink;
using sim::SimTelloLink;
using sim::parse_world_mode;
using sim::read_sim_config_of;
using sim::sim_tello_settings;
using sim::to_string;


std::vector<OptionSpec> experiment_option_specs() {
  return {{"--seed", "N", "first random seed (default 1); run i uses seed + i"},
          {"--runs", "N", "number of seeded runs (default 1)"},
          {"--json", "", "print the summary as JSON"},
          {"--out", "DIR", "write CSV per run, an SVG plot of the first run and summary.json"},
          {"--config", "FILE", "configuration: its control, estimation and vision sections; with --route its lab; with --vision real its lab, cameras, front ends (planar, slam, face) and sim (default config/default.json)"}};
}

std::vector<OptionSpec> real_vision_option_specs() {
  return {{"--vision", "model|real",
           "model (default): quadrotor and perception models; real: the simulated lab with rendered cameras and the "
           "real vision pipelines"},
          {"--fps", "N", "with --vision real: frames rendered and processed per second (default 30)"},
          {"--world", "nominal|randomized",
           "with --vision real: the simulated lab's world: nominal, the configuration exactly; randomized, a world drawn "
           "around it per seed (the drone, sensor biases, placements, cameras, delays, light, Wi-Fi losses; docs/sim.md) "
           "that the flight software does not see (default: the config's sim.world)"},
          {"--calibrated-cameras", "",
           "with --world randomized: the drawn world's cameras have the configured intrinsics and distortion exactly (each "
           "drone calibrated); everything else is drawn as before"},
          {"--nominal-factors", "LIST",
           "with --world randomized: these factors keep the configuration's values, every other one is drawn as in "
           "the whole randomized world of the same seed (comma-separated: drone, sensors, placements, lens, mounting, "
           "delays, lighting, link, teacher)"},
          {"--world-factors", "LIST",
           "with --world randomized: only these factors are drawn (as in the whole randomized world of the same "
           "seed), the others keep the configuration's values (the same names as --nominal-factors)"},
          {"--drone-model", "ardrone|tello",
           "with --vision real: the drone the lab is flown as: ardrone (default), the AR.Drone 2.0 (SimDroneLink); tello, a "
           "Tello in SDK mode (SimTelloLink: its state string at 10 Hz in whole degrees and dm/s, its sticks, its "
           "cameras from the config's tello section: the front one, and the Tello EDU's downward one with "
           "tello.link.downvision and tello.emulator.downvision), the flight software with the tello section's "
           "estimation settings"},
          {"--vision-latency", "inline|worker",
           "with --vision real: inline (default): each frame's vision is done before the next control tick; worker: as "
           "labodrone serve runs it, a frame's results reach the estimator after the worker's modelled time and frames "
           "that come while it is busy are skipped"}};
}

namespace {

sim::WorldFactorSet parse_factor_list(const std::string& option, const std::string& list) {
  sim::WorldFactorSet set;
  std::string_view rest = list;
  for (;;) {
    const std::size_t comma = rest.find(',');
    const std::string_view name = rest.substr(0, comma);
    const auto factor = sim::parse_world_factor(name);
    if (!factor) {
      throw UsageError(option + ": '" + std::string(name) +
                       "' is not a factor (expected a comma-separated list of drone, sensors, placements, lens, "
                       "mounting, delays, lighting, link, teacher)");
    }
    set.insert(*factor);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return set;
}

sim::WorldFactorSet read_nominal_factors(const ParsedArgs& args, std::optional<WorldMode> world) {
  const auto nominal = args.value("--nominal-factors");
  const auto drawn = args.value("--world-factors");
  if (!nominal && !drawn) return {};
  const std::string option = nominal ? "--nominal-factors" : "--world-factors";
  if (nominal && drawn) throw UsageError("--nominal-factors and --world-factors: give one or the other");
  if (world != WorldMode::Randomized)
    throw UsageError(option + " needs --world randomized (the nominal world has every factor at the configuration's values)");
  if (nominal) return parse_factor_list(option, *nominal);
  const sim::WorldFactorSet only = parse_factor_list(option, *drawn);
  sim::WorldFactorSet kept;
  for (sim::WorldFactor f : sim::kWorldFactors)
    if (!only.contains(f)) kept.insert(f);
  return kept;
}

}  // namespace

OptionSpec jobs_option_spec() {
  return {"--jobs", "N", "fly N runs at once on N threads (default 1); each run's result is the same as alone"};
}

ExperimentOptions read_experiment_options(const ParsedArgs& args) {
  ExperimentOptions o;
  const std::string vision = args.value_or("--vision", "model");
  if (vision != "model" && vision != "real") throw UsageError("--vision must be model or real (got '" + vision + "')");
  o.real_vision = vision == "real";
  if (args.value("--fps")) {
    if (!o.real_vision) throw UsageError("--fps needs --vision real");
    o.video_fps = args.number_or("--fps", 30.0, 1.0, 60.0);
  }
  if (const auto latency = args.value("--vision-latency")) {
    if (*latency != "inline" && *latency != "worker")
      throw UsageError("--vision-latency must be inline or worker (got '" + *latency + "')");
    if (!o.real_vision) throw UsageError("--vision-latency needs --vision real");
    if (*latency == "worker") o.vision_latency = VisionLatencyModel{};
  }
  if (const auto world = args.value("--world")) {
    o.world = parse_world_mode(*world);
    if (!o.world) throw UsageError("--world must be nominal or randomized (got '" + *world + "')");
    if (!o.real_vision) throw UsageError("--world needs --vision real (the models fly no simulated lab)");
  }
  const bool calibrated_cameras = args.flag("--calibrated-cameras");
  if (calibrated_cameras && o.world != WorldMode::Randomized)
    throw UsageError("--calibrated-cameras needs --world randomized (the nominal world's cameras are calibrated already)");
  if (calibrated_cameras && (args.value("--nominal-factors") || args.value("--world-factors")))
    throw UsageError("--calibrated-cameras with --nominal-factors or --world-factors: give the lens in the list instead");
  o.nominal_factors = read_nominal_factors(args, o.world);
  if (calibrated_cameras) o.nominal_factors.insert(sim::WorldFactor::Lens);
  if (const auto model = args.value("--drone-model")) {
    if (*model != "ardrone" && *model != "tello")
      throw UsageError("--drone-model must be ardrone or tello (got '" + *model + "')");
    if (!o.real_vision) throw UsageError("--drone-model needs --vision real (the models fly no simulated lab)");
    o.tello = *model == "tello";
  }
  o.seed = static_cast<unsigned>(args.integer_or("--seed", 1, 0, 1 << 30));
  o.runs = args.integer_or("--runs", 1, 1, 10000);
  if (args.value("--jobs")) o.jobs = args.integer_or("--jobs", 1, 1, 64);
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

namespace {
LabDescription load_lab_file(const std::filesystem::path& config, const ConfigReader& root) {
  return load_lab_description((config.parent_path() / root.string_or("lab", "lab.json")).lexically_normal());
}
}  // namespace

Experiment make_experiment(const ExperimentOptions& options, bool with_face) {
  Experiment e;
  control::FlightStackSetup& setup = e.setup;
  const ConfigDocument doc = ConfigDocument::load(options.config);
  const ConfigReader root = doc.root();
  if (root.has("control")) setup.control = control::read_control_config(root.object("control"));
  if (root.has("estimation")) setup.estimation = estimation::read_estimation_config(root.object("estimation"));
  if (root.has("vision")) setup.vision = read_vision_thresholds(root.object("vision"));
  if (!options.real_vision) {
    // The models deliver navdata and vision results without latency and act on commands at once:
    // the estimator's delay compensation must not shift them.
    setup.estimation.video_delay_s = 0;
    setup.estimation.navdata_delay_s = 0;
    setup.estimation.control_delay_s = 0;
    setup.lab = model_lab();
    return e;
  }
  // SimDroneLink has the link's delays: the estimator keeps the configured ones.
  const std::filesystem::path base_dir = options.config.parent_path();
  e.lab = load_lab_file(options.config, root);
  setup.lab = fusion::lab_geometry_from(*e.lab);
  if (root.has("cameras")) setup.cameras = read_cameras_config(root.object("cameras"));
  if (options.tello) {
    // What `serve --drone tello` flies with: the Tello's camera in front, its estimation settings.
    const TelloConfig tello = read_tello_config_of(root);
    setup.cameras = tello_cameras(tello, setup.cameras);
    if (root.has("tello") && root.object("tello").has("estimation"))
      setup.estimation = estimation::read_estimation_config(root.object("tello").object("estimation"), setup.estimation);
    e.tello = sim_tello_settings(tello);
  }
  fusion::FrontEndSettings front_ends = fusion::read_front_end_settings(root, base_dir);
  front_ends.slam.mapping_mode = slam::MappingMode::Synchronous;  // lockstep: the same flight every time
  front_ends.with_face = with_face;
  setup.front_ends = front_ends;
  e.sim = read_sim_config_of(root);
  if (options.world) e.sim.world = *options.world;
  if (options.video_fps) e.sim.link.video_fps = *options.video_fps;
  e.vision_latency = options.vision_latency;
  if (with_face) e.head = face::load_lab_teacher_head(*e.lab, front_ends.face);
  // Without the face there is nothing to follow, and the flight software does not avoid a teacher
  // walking into its way: the teacher keeps to the lab file's path, clear of the stand-offs.
  if (!with_face) e.world_ranges.teacher_walk.reset();
  e.world_ranges.nominal = options.nominal_factors;
  return e;
}

std::unique_ptr<ExperimentFlight> make_flight(const Experiment& experiment, unsigned seed) {
  if (!experiment.lab) return std::make_unique<LockstepFlight>(experiment.setup, PerceptionModelConfig{}, seed);
  SimConfig sim = experiment.sim;
  sim.lab.seed = seed;
  sim.link.seed = seed;
  return std::make_unique<SimLabFlight>(experiment.setup, *experiment.lab, sim, experiment.head, experiment.vision_latency,
                                        experiment.world_ranges, experiment.tello);
}

std::string world_name(const Experiment& experiment) { return experiment.lab ? to_string(experiment.sim.world) : "none"; }

nlohmann::json run_world_json(const ExperimentFlight& flight) {
  return flight.world() ? world_json(*flight.world(), flight.now()) : nlohmann::json();
}

void write_run_outputs(const ExperimentOptions& options, const std::string& name, int index, const ExperimentFlight& flight) {
  if (!options.out) return;
  const std::string stem = name + "_seed" + std::to_string(options.seed + static_cast<unsigned>(index));
  write_flight_csv(*options.out / (stem + ".csv"), flight.samples());
  if (index == 0)
    write_flight_svg(*options.out / (stem + ".svg"), flight.samples(),
                     "labodrone sim " + name + " (seed " + std::to_string(options.seed) + "; " + flight.description() + ")");
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

std::string real_vision_note(const ExperimentOptions& options) {
  if (options.real_vision && options.tello)
    return "vehicle: simulated lab (drone/sim) in the run's world, flown as a Tello through SimTelloLink (TelloFirmware, "
           "the state string at 10 Hz, rc sticks, the Tello's front camera and the Tello EDU's downward camera (downvision), link timing and delays); perception: the "
           "real vision front-ends (planar, SLAM, face); estimator: StateEstimator with the tello section's settings";
  return options.real_vision
             ? "vehicle: simulated lab (drone/sim: rigid-body quadrotor under the firmware's inner loops, sensor model, "
               "LabRenderer cameras) in the run's world, through SimDroneLink (link timing and delays); perception: the real "
               "vision front-ends (planar, SLAM, face); estimator: StateEstimator"
             : "vehicle: quadrotor model (bench/experiments/quadrotor_model.hpp); perception: model (no rendering); "
               "estimator: StateEstimator";
}

std::string fmt(const char* format, double a, double b, double c) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
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

}  // namespace labo::bench
