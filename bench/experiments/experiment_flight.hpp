#pragma once
// A flight the lockstep experiments can run: FlightStack over some simulated drone, ticked at the
// control rate, recording estimated, true and desired pose with the localization source and stage.
// Two kinds: LockstepFlight (the quadrotor and perception models, lockstep_flight.hpp) and
// SimLabFlight (the simulated lab with rendered cameras and the real vision front-ends,
// sim_lab_flight.hpp). The experiments' measurements use the truth through this interface only.
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench/experiments/lockstep_vision_worker.hpp"
#include "control/flight_stack.hpp"
#include "core/frames.hpp"
#include "drone/sim/sim_world.hpp"
#include "localization/estimation/state_estimator.hpp"

namespace labo::bench {

using sim::SimWorld;


// The estimator's counters a recovery's timeline needs (StateEstimator::statistics(), running totals).
struct EstimatorCounts {
  std::uint64_t object_fused = 0;
  std::uint64_t slam_fused = 0;
  std::uint64_t rejected_reacquisition = 0;
  std::uint64_t reacquisition_confirmed = 0;
  std::uint64_t rejected_innovation = 0;
  std::uint64_t rejected_jump = 0;  // beyond D or beta
  std::uint64_t velocity_dropouts = 0;         // bottom-camera velocity dropouts detected (onsets)
  std::uint64_t velocity_dropout_packets = 0;  // navdata packets whose velocity was not fused
};
EstimatorCounts estimator_counts(const estimation::StateEstimator& estimator);

struct FlightSample {
  Seconds t = 0;
  Eigen::Vector4d estimated = Eigen::Vector4d::Zero();  // x, y, z, yaw
  Eigen::Vector4d truth = Eigen::Vector4d::Zero();
  std::optional<Eigen::Vector4d> desired;
  fusion::FeedbackSource source = fusion::FeedbackSource::DeadReckoning;
  fusion::SlamState slam = fusion::SlamState::Off;
  fusion::TrackState target = fusion::TrackState::Off;  // the platform in stage 5, else the instrument (or the face)
  std::string target_reason;            // why the target is lost, as its front-end says
  std::string target_method;            // how it is tracked (face: the pose method, or "head" without a face)
  int stage_index = 0;
  std::string stage;
  // The teacher's face, when there is one (face-follow diagnostics): true place in the world (x, y, z,
  // heading of the face's +z), true and measured position in the front camera (z = depth).
  std::optional<Eigen::Vector4d> face_true_world;
  std::optional<Eigen::Vector3d> face_true_cam;
  std::optional<Eigen::Vector3d> face_measured_cam;
  // What control did and why (diagnostics of recoveries): the move command sent (roll, pitch, gaz,
  // yaw rate; zero when the action was not a move), the action, the active safety alerts joined by
  // "; ", and the estimator's running counts of the vision inputs it fused or refused.
  Eigen::Vector4d command = Eigen::Vector4d::Zero();
  std::string action;
  std::string alerts;
  EstimatorCounts estimator;
  Eigen::Vector2d estimated_velocity = Eigen::Vector2d::Zero();  // world x, y (the estimate's, m/s)
  double position_sigma_m = 0;  // the estimate's 1-sigma position uncertainty
  double drift_bound_m = 0;     // ... and how far dead reckoning may have drifted
};

// The lab as it really is, which the experiments measure against: where the instruments and the
// platform stand, the front camera's intrinsics and mounting. The flight software never sees it (it
// flies with the configuration's); for the models' flights and a nominal world it is the configuration.
struct TrueLab {
  fusion::LabGeometry lab;
  CameraIntrinsics front;
  Eigen::Isometry3d T_body_front = T_body_cam_front();
};

class ExperimentFlight {
 public:
  static constexpr double kControlDt = 1.0 / 30.0;

  virtual ~ExperimentFlight() = default;
  virtual void tick() = 0;  // one control period
  virtual control::FlightStack& stack() = 0;
  virtual Seconds now() const = 0;
  virtual Eigen::Isometry3d true_pose() const = 0;  // T_world_body
  // The teacher's face (face frame, z out of the face) when there is one to follow.
  virtual std::optional<Eigen::Isometry3d> true_face() const = 0;
  // The teacher starts walking (the model's scripted walk; the simulated lab's teacher keeps to the
  // lab file's path on their own).
  virtual void start_teacher_walk() = 0;
  // An external push (the paper's impulses, `sim perturb`): a velocity change (world, m/s) and a yaw
  // kick that turns the drone by about dyaw_rad, at once.
  virtual void push(const Eigen::Vector3d& dv_world_mps, double dyaw_rad) = 0;
  virtual bool crashed() const = 0;
  virtual const fusion::LabGeometry& lab() const = 0;  // the flight software's lab (the configuration's)
  virtual const TrueLab& true_lab() const = 0;
  // The simulated lab's world (drawn values included) for the run's output; none for the models.
  virtual const SimWorld* world() const { return nullptr; }
  virtual const std::vector<FlightSample>& samples() const = 0;
  // What flew and what saw, for plot titles and summaries.
  virtual std::string description() const = 0;
  // The modelled vision worker's frame counts (--vision-latency worker), when the flight has one.
  virtual std::optional<LockstepVisionStats> vision_stats() const { return std::nullopt; }

  bool run_until(const std::function<bool()>& done, double timeout_s);
  void run(double seconds);
  control::CommandResult request(const control::MissionRequest& r) { return stack().request(r, now()); }
  // The true pose of the front camera (as it is mounted) relative to a target (z into it).
  Eigen::Isometry3d true_T_cam(const Eigen::Isometry3d& T_world_target) const;
  // The instrument `id` (or the platform) where it really is; throws std::invalid_argument when the
  // lab has no such instrument.
  const fusion::PlanarTarget& true_instrument(const std::string& id) const;
};

Eigen::Vector4d xyz_yaw(const Eigen::Isometry3d& T);
// The sample of this tick, from the stack's status, the action it decided, the estimator and the
// truth (the teacher's face: T_world_face).
FlightSample sample_of(const control::FlightStatus& status, const control::FlightOutput& out, const estimation::StateEstimator& estimator,
                       const Eigen::Isometry3d& truth, Seconds t, const std::optional<Eigen::Isometry3d>& true_face);

}  // namespace labo::bench
