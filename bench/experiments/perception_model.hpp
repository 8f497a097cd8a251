#pragma once
// A perception model for the lockstep experiments while the simulated lab's renderer and the vision
// pipelines are not in the loop: from the true pose it produces what the vision front-ends would -
// the instrument's and platform's camera poses (in the field of view, in range, facing the camera,
// noise growing with the square of the distance), the face's, and SLAM camera poses in an unscaled map
// that is lost when the panel fills the view (the paper's §6.3 observation: too few keypoints near
// the instrument). Seeded; every figure it produces is labelled "perception: model".
#include <optional>
#include <random>

#include "bench/experiments/quadrotor_model.hpp"
#include "localization/fusion/lab_pipelines.hpp"

namespace labo::bench {

struct PerceptionModelConfig {
  double instrument_range_m = 4.5;
  double face_range_m = 4.0;
  double position_noise_at_1m = 0.006;  // 1-sigma, metres, scaled by distance^2
  double angle_noise_rad = 0.01;
  double slam_lost_below_m = 1.3;       // panel closer than this fills the view: SLAM lost
  double slam_noise_m = 0.02;
  double map_units_per_m = 0.6;         // the unknown scale the estimator must learn
  double slam_init_s = 3.0;             // airborne this long before SLAM is good
  double navdata_velocity_noise_mps = 0.03;
  double navdata_altitude_noise_m = 0.005;
};

// One video frame's worth of vision results, as the front-ends would hand them over; recorded for
// offline replays (sim compare-slam).
struct PerceptionFrame {
  Seconds t = 0;
  std::optional<fusion::TargetObservation> instrument, platform, face;
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  fusion::SlamSummary slam;
  void deliver_to(fusion::LabPipelines& pipelines) const;
};

class PerceptionModel {
 public:
  PerceptionModel(PerceptionModelConfig config, fusion::LabGeometry lab, unsigned seed);
  // Navdata with noise from the model.
  NavdataSample navdata(const QuadrotorModel& drone, Seconds t);
  // One video frame's worth of vision results at time t for what `focus` asks for.
  PerceptionFrame observe(const QuadrotorModel& drone, const Eigen::Isometry3d& T_world_face, Seconds t,
                          const fusion::PerceptionFocus& focus);

 private:
  Eigen::Isometry3d noisy(const Eigen::Isometry3d& T, double distance);
  double gauss(double sigma) { return sigma * normal_(rng_); }

  PerceptionModelConfig config_;
  fusion::LabGeometry lab_;
  std::mt19937 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Seconds airborne_since_ = -1;
  Eigen::Isometry3d T_map_world_ = Eigen::Isometry3d::Identity();
};

}  // namespace labo::bench
