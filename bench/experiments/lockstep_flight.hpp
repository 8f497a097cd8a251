#pragma once
// One lockstep flight for the experiments (an ExperimentFlight): FlightStack (with LabPipelines and
// the StateEstimator) flying the QuadrotorModel, the PerceptionModel standing in for rendered frames and vision, a teacher
// whose face can walk. 30 Hz control ticks, 5 physics sub-steps each. Records estimated, true and
// desired pose with the localization source and mission stage for the CSV files and plots.
#include <memory>
#include <string>
#include <vector>

#include "bench/experiments/experiment_flight.hpp"
#include "bench/experiments/perception_model.hpp"

namespace labo::bench {

// Everything the localization saw in one tick, for offline replays.
struct TickRecord {
  NavdataSample navdata;
  fusion::PerceptionFocus focus;  // what the live system asked for (its source choice included)
  PerceptionFrame frame;
  std::optional<MoveCommand> command;
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
};

class LockstepFlight final : public ExperimentFlight {
 public:
  LockstepFlight(const control::FlightStackSetup& setup, const PerceptionModelConfig& perception, unsigned seed);

  void tick() override;
  control::FlightStack& stack() override { return *stack_; }
  Seconds now() const override { return t_; }
  Eigen::Isometry3d true_pose() const override { return drone_.pose(); }
  // The face frame with z out of the face (T_world_face_ is control's convention, z into it).
  std::optional<Eigen::Isometry3d> true_face() const override;
  // Back and forth along y between -1 and 1 m at 0.5 m/s, turning with a human 0.5 m/s^2.
  void start_teacher_walk() override { walking_ = true; }
  void push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad) override { drone_.push(dv_world_mps, dyaw_rad); }
  bool crashed() const override { return drone_.crashed; }
  const fusion::LabGeometry& lab() const override { return lab_; }
  const TrueLab& true_lab() const override { return true_lab_; }  // the models' lab is the configuration
  const std::vector<FlightSample>& samples() const override { return samples_; }
  std::string description() const override { return "quadrotor model, perception model"; }

  QuadrotorModel& drone() { return drone_; }
  Eigen::Isometry3d& face() { return T_world_face_; }
  void set_recording(bool on) { recording_ = on; }
  const std::vector<TickRecord>& records() const { return records_; }

 private:
  fusion::LabGeometry lab_;
  TrueLab true_lab_;
  QuadrotorModel drone_;
  PerceptionModel perception_;
  fusion::LabPipelines* pipelines_ = nullptr;  // owned by stack_
  std::unique_ptr<control::FlightStack> stack_;
  void walk_teacher();

  Eigen::Isometry3d T_world_face_ = Eigen::Isometry3d::Identity();
  bool walking_ = false;
  double walk_direction_ = 1.0, walk_speed_ = 0.0;
  std::vector<FlightSample> samples_;
  Seconds t_ = 0;
  bool recording_ = false;
  std::vector<TickRecord> records_;
};

}  // namespace labo::bench
