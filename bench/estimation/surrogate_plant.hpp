#pragma once
// SurrogatePlant: a stand-in AR.Drone for the estimation experiments, independent of the simulated
// lab and kept for comparison (`sim estimate --plant surrogate`). Its physics deliberately differ from
// the estimator's model (second-order attitude loops, quadratic drag, wind gusts, a vertical-speed
// loop with lag) and its sensors have the AR.Drone's flaws (noise, a bottom-camera velocity scale
// error, yaw drift, an ultrasound that sees benches), so the filter and the model fit are not tested
// against their own equations. Link delays: navdata 40 ms, commands 100 ms, video 75 ms
// (configurable). It renders no frames (truth-derived vision only).
// Seeded and deterministic.
#include <deque>
#include <random>

#include "bench/estimation/estimation_plant.hpp"

namespace labo::bench {

struct SurrogatePlantOptions {
  Seconds navdata_period = 1.0 / 200.0;
  Seconds navdata_delay = 0.040;
  Seconds command_delay = 0.100;
  Seconds video_delay = 0.075;
  double velocity_scale_error = 0.03;  // bottom camera reads 3 % high
  double gust_accel_mps2 = 0.05;       // draughts and the drone's own turbulence (Ornstein-Uhlenbeck)
  Eigen::Vector3d start = Eigen::Vector3d(0, 0, 1.0);
};

class SurrogatePlant final : public EstimationPlant {
 public:
  SurrogatePlant(unsigned seed, const SurrogatePlantOptions& options = {});

  std::string name() const override { return "surrogate"; }
  Seconds now() const override { return t_; }
  void move(const MoveCommand& command) override;
  void step(Seconds dt, std::vector<NavdataSample>& arrived) override;
  GroundTruth truth() const override;
  std::string crash() const override { return {}; }  // no obstacles
  const std::vector<VideoFrame>& frames_of_last_step() const override { return no_frames_; }
  void push(const Eigen::Vector3d& delta_v_world) override { v_ += delta_v_world; }
  // Its vertical loop (4 /s behind a 12 /s lag) under the experiments' z loop: 2.6 m/s lifts 0.5 m.
  double vertical_push_for(double metres) const override { return 5.2 * metres; }
  estimation::SurfaceMap surfaces() const override { return surfaces_; }
  // A panel at (3, 0, 1.2) facing the base, over a bench.
  PlantInstrument instrument() const override;
  Seconds command_latency() const override { return options_.command_delay; }
  Seconds video_delay() const override { return options_.video_delay; }
  Seconds navdata_delay() const override { return options_.navdata_delay; }

 private:
  void integrate(double dt);
  NavdataSample sense();

  SurrogatePlantOptions options_;
  std::mt19937 rng_;
  Seconds t_ = 0;
  Seconds next_navdata_ = 0;
  Eigen::Vector3d p_, v_ = Eigen::Vector3d::Zero();
  double roll_ = 0, pitch_ = 0, yaw_ = 0;
  double roll_rate_ = 0, pitch_rate_ = 0, yaw_rate_ = 0, vz_cmd_lag_ = 0;
  Eigen::Vector2d gust_ = Eigen::Vector2d::Zero();
  double yaw_drift_ = 0;
  MoveCommand active_;
  std::deque<std::pair<Seconds, MoveCommand>> commands_in_flight_;
  std::deque<NavdataSample> navdata_in_flight_;
  estimation::SurfaceMap surfaces_;
  std::vector<VideoFrame> no_frames_;
};

}  // namespace labo::bench
