#include "bench/estimation/lab_plant.hpp"

#include <stdexcept>

#include "drone/sim/sim_setup.hpp"

namespace labo::bench {

using lab::InstrumentSpec;

using sim::Disturbance;
using sim::FirmwarePhase;
using sim::QuadrotorState;
using sim::SimDroneLink;
using sim::SimulatedLabSettings;
using sim::make_simulated_lab;


namespace {
constexpr Seconds kTakeoffLimit = 10.0;
constexpr Seconds kWholeRun = 1e6;
}  // namespace

LabPlant::LabPlant(const LabPlantInputs& inputs, const PlantRequest& request) : link_settings_(inputs.sim.link) {
  for (const InstrumentSpec& spec : inputs.lab.instruments)
    if (spec.id == inputs.instrument_id) instrument_ = {spec.id, spec.T_world_object};
  if (instrument_.id.empty()) throw std::invalid_argument("LabPlant: the lab has no instrument '" + inputs.instrument_id + "'");
  SimulatedLabSettings lab_settings = inputs.sim.lab;
  lab_settings.seed = request.seed;
  if (!request.video) lab_settings.disturbances.push_back({Disturbance::Kind::VideoDropout, 0.0, kWholeRun});
  link_settings_.seed = request.seed;
  link_settings_.full_navdata = request.navdata_period < 0.5 / link_settings_.demo_rate_hz;
  lab_ = make_simulated_lab(inputs.lab, inputs.cameras, lab_settings, inputs.head);
  link_ = std::make_unique<SimDroneLink>(*lab_, link_settings_);
  link_->set_listener(this);
  surfaces_ = estimation::surface_map_of(inputs.lab);
  frames_.reserve(8);
  pixels_.resize(8);
  // Flat trim on the platform (unless asked not to), take off, wait for the firmware's hover (navdata
  // meanwhile dropped).
  if (request.flat_trim) link_->flat_trim();
  link_->advance_to(0.2);
  link_->takeoff();
  while (link_->now() < kTakeoffLimit && lab_->truth().phase != FirmwarePhase::Hovering) link_->advance_to(link_->now() + 0.05);
  if (lab_->truth().phase != FirmwarePhase::Hovering)
    throw std::runtime_error("LabPlant: the take-off did not end in a hover within 10 s");
  link_->advance_to(link_->now() + 0.5);
}

LabPlant::~LabPlant() = default;

void LabPlant::on_navdata(const NavdataSample& sample) {
  if (arrived_) arrived_->push_back(sample);
}

void LabPlant::on_video(const VideoFrame& frame) {
  if (!arrived_) return;  // during the take-off
  const std::size_t i = frames_.size();
  if (i == pixels_.size()) pixels_.emplace_back();
  frame.bgr.copyTo(pixels_[i]);  // reuses the buffer at a steady size
  frames_.push_back({frame.t, frame.camera, frame.frame_number, pixels_[i]});
}

void LabPlant::step(Seconds dt, std::vector<NavdataSample>& arrived) {
  frames_.clear();
  arrived_ = &arrived;
  link_->advance_to(link_->now() + dt);
  arrived_ = nullptr;
}

GroundTruth LabPlant::truth() const {
  const QuadrotorState& s = lab_->truth();
  GroundTruth g;
  g.t = s.t;
  g.T_world_body = s.T_world_body();
  g.velocity_world = s.velocity_mps;
  g.yaw_rate = s.yaw_rate_radps;
  return g;
}

std::string LabPlant::crash() const {
  const QuadrotorState& s = lab_->truth();
  if (s.crashes == 0) return {};
  return s.crash_reason.empty() ? std::string("a crash") : s.crash_reason;
}

double LabPlant::vertical_push_for(double metres) const {
  // The firmware's vertical-speed lag (0.8 /s) under the experiments' z loop, measured on this plant:
  // 0.75 m/s lifts it about 0.5 m (the results report the peak reached).
  return 1.5 * metres;
}

Seconds LabPlant::command_latency() const {
  // The driver resends the current command every AT period; on average a new one waits half of it.
  return link_settings_.command_delay_s + 0.5 * link_settings_.command_interval_s;
}

}  // namespace labo::bench
