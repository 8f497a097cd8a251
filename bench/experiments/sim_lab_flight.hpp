#pragma once
// One lockstep flight in the simulated lab with FlightStack running the real vision front-ends on the
// rendered frames (`labodrone-bench sim ... --vision real`): SimulatedLab (drone/sim/: the firmware's
// dynamics, the sensor model, the walking teacher, LabRenderer's cameras) behind SimDroneLink, the
// lockstep DroneLink with the real link's timing (15 Hz demo navdata, 30 fps video, delays, jitter,
// the driver's 30 ms AT loop, the camera switch delay; docs/sim.md). Each control period the link
// advances to now, delivering navdata and frames to the stack; the stack ticks and its action goes to
// the link, exactly as the server's runtime does with the real driver. Each frame's vision runs before
// the next tick, or, given a latency model, as the server's vision worker runs it: its results applied
// after the worker's modelled time, frames skipped while it is busy (lockstep_vision_worker.hpp).
// Given Tello settings, the lab is flown through SimTelloLink instead (drone/sim/sim_tello_link.hpp:
// the Tello's firmware, state string, sticks and single camera); `setup` then describes a Tello.
#include <memory>
#include <optional>

#include "bench/experiments/experiment_flight.hpp"
#include "bench/experiments/lockstep_vision_worker.hpp"
#include "localization/fusion/lab_pipelines.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/head_model.hpp"
#include "drone/sim/sim_config.hpp"
#include "drone/sim/sim_drone_link.hpp"
#include "drone/sim/sim_tello_link.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo::bench {

using sim::LabRenderer;
using sim::LockstepDroneLink;
using sim::SimConfig;
using sim::SimDroneLink;
using sim::SimTelloLink;
using sim::SimTelloSettings;
using sim::SimWorld;
using sim::SimulatedLab;
using sim::TexturedHeadModel;
using sim::WorldRanges;
using sim::make_sim_world;


class SimLabFlight final : public ExperimentFlight {
 public:
  // `setup.front_ends` must be set: this flight has no other perception than the rendered frames.
  // `sim` is the lab's and the link's settings (their seeds included) and the world's mode: the
  // simulated lab flies make_sim_world(lab, setup.cameras, sim, ranges), the flight stack only
  // `setup`. `head` textures the teacher's face.
  SimLabFlight(const control::FlightStackSetup& setup, const lab::LabDescription& lab, const SimConfig& sim,
               std::optional<TexturedHeadModel> head, std::optional<VisionLatencyModel> vision_latency = std::nullopt,
               const WorldRanges& ranges = {}, std::optional<SimTelloSettings> tello = std::nullopt);
  ~SimLabFlight() override;

  void tick() override;
  control::FlightStack& stack() override { return *stack_; }
  Seconds now() const override { return t_; }
  Eigen::Isometry3d true_pose() const override { return lab_->truth().T_world_body(); }
  std::optional<Eigen::Isometry3d> true_face() const override;
  void start_teacher_walk() override {}  // the world's teacher walks all along
  void push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad) override { lab_->dynamics().push(dv_world_mps, dyaw_rad); }
  bool crashed() const override { return lab_->truth().crashes > 0; }
  const fusion::LabGeometry& lab() const override { return geometry_; }
  const TrueLab& true_lab() const override { return true_lab_; }
  const SimWorld* world() const override { return &world_; }
  const std::vector<FlightSample>& samples() const override { return samples_; }
  std::string description() const override;

  SimulatedLab& simulated_lab() { return *lab_; }
  const LockstepDroneLink& link() const { return *link_; }
  // With a latency model: the modelled worker's frame counts.
  std::optional<LockstepVisionStats> vision_stats() const override;

 private:
  struct Listener;
  void apply(const control::FlightOutput& out);

  fusion::LabGeometry geometry_;
  SimWorld world_;
  TrueLab true_lab_;
  std::unique_ptr<SimulatedLab> lab_;
  std::unique_ptr<control::FlightStack> stack_;
  const fusion::LabPipelines* pipelines_ = nullptr;  // owned by stack_
  std::unique_ptr<LockstepVisionWorker> vision_worker_;  // with a latency model
  std::unique_ptr<Listener> listener_;
  std::unique_ptr<LockstepDroneLink> link_;
  bool tello_ = false;
  double telemetry_hz_ = 0;  // navdata or state strings per second
  Seconds t_ = 0;
  std::vector<FlightSample> samples_;
};

}  // namespace labo::bench
