#pragma once
// One lockstep flight in the simulated lab (drone/sim/SimulatedLab: the firmware's dynamics, the
// sensor model, rendered cameras) with FlightStack running the real vision front-ends on the rendered
// frames (`labodrone sim ... --vision real`). Each control period: the lab advances, its navdata goes
// to the stack, the selected camera is rendered at the video rate and handed to on_video(), the stack
// ticks and its action is applied to the lab. Navdata and frames arrive without link delay (the
// estimator's delays must be 0, as experiment_setup() sets them).
#include <memory>

#include "control/experiments/experiment_flight.hpp"
#include "drone/lab/lab_description.hpp"
#include "drone/sim/simulated_lab.hpp"

namespace labo {

struct SimLabFlightOptions {
  double video_fps = 30;  // rendered and processed frames per second
  unsigned seed = 1;      // the lab's sensor noise
};

class SimLabFlight final : public ExperimentFlight {
 public:
  // `setup.front_ends` must be set: this flight has no other perception than the rendered frames.
  SimLabFlight(const FlightStackSetup& setup, const LabDescription& lab, const SimLabFlightOptions& options);

  void tick() override;
  FlightStack& stack() override { return *stack_; }
  Seconds now() const override { return t_; }
  Eigen::Isometry3d true_pose() const override { return lab_->truth().T_world_body(); }
  std::optional<Eigen::Isometry3d> true_face() const override;
  void start_teacher_walk() override {}
  bool crashed() const override { return lab_->truth().crashes > 0; }
  const LabGeometry& lab() const override { return geometry_; }
  const std::vector<FlightSample>& samples() const override { return samples_; }
  std::string description() const override;

  SimulatedLab& simulated_lab() { return *lab_; }
  int frames_processed() const { return frames_; }

 private:
  void apply(const FlightOutput& out);

  LabGeometry geometry_;
  SimLabFlightOptions options_;
  std::unique_ptr<SimulatedLab> lab_;
  std::unique_ptr<FlightStack> stack_;
  VideoFrame frame_;  // its image is reused frame after frame
  Seconds t_ = 0;
  Seconds next_frame_t_ = 0;
  int frames_ = 0;
  std::vector<FlightSample> samples_;
};

}  // namespace labo
