#pragma once
// One lockstep flight for the experiments: FlightStack (with LabPipelines and the StateEstimator)
// flying the QuadrotorModel, the PerceptionModel standing in for rendered frames and vision, a teacher
// whose face can walk. 30 Hz control ticks, 5 physics sub-steps each. Records estimated, true and
// desired pose with the localization source and mission stage for the CSV files and plots.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "control/experiments/perception_model.hpp"
#include "control/flight_stack.hpp"

namespace labo {

struct FlightSample {
  Seconds t = 0;
  Eigen::Vector4d estimated = Eigen::Vector4d::Zero();  // x, y, z, yaw
  Eigen::Vector4d truth = Eigen::Vector4d::Zero();
  std::optional<Eigen::Vector4d> desired;
  FeedbackSource source = FeedbackSource::DeadReckoning;
  int stage_index = 0;
  std::string stage;
};

class LockstepFlight {
 public:
  LockstepFlight(const FlightStackSetup& setup, const PerceptionModelConfig& perception, unsigned seed);

  void tick();  // one control period
  bool run_until(const std::function<bool()>& done, double timeout_s);
  void run(double seconds);
  CommandResult request(const MissionRequest& r) { return stack_->request(r, t_); }

  FlightStack& stack() { return *stack_; }
  QuadrotorModel& drone() { return drone_; }
  Eigen::Isometry3d& face() { return T_world_face_; }
  Seconds now() const { return t_; }
  const std::vector<FlightSample>& samples() const { return samples_; }
  const LabGeometry& lab() const { return lab_; }
  // The true camera pose of the front camera relative to a target (z into it).
  Eigen::Isometry3d true_T_cam(const Eigen::Isometry3d& T_world_target) const;

  static constexpr double kControlDt = 1.0 / 30.0;

 private:
  LabGeometry lab_;
  QuadrotorModel drone_;
  PerceptionModel perception_;
  LabPipelines* pipelines_ = nullptr;  // owned by stack_
  std::unique_ptr<FlightStack> stack_;
  Eigen::Isometry3d T_world_face_ = Eigen::Isometry3d::Identity();
  std::vector<FlightSample> samples_;
  Seconds t_ = 0;
};

Eigen::Vector4d xyz_yaw(const Eigen::Isometry3d& T);

}  // namespace labo
